#include "ballagg/run/verify_run.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "ballagg/analysis/cluster_partition.hpp"
#include "ballagg/analysis/cluster_unwrapping.hpp"
#include "ballagg/config/text_file.hpp"
#include "ballagg/core/disjoint_sets.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/core/spin.hpp"
#include "ballagg/io/csv_reader.hpp"
#include "ballagg/io/state_csv.hpp"
#include "ballagg/run/run_directory.hpp"
#include "ballagg/run/verify_trajectory.hpp"
#include "ballagg/spatial/pair_scan.hpp"

namespace ballagg {
namespace {

// How many pairs or spheres a violation line names at most (the count is always given).
constexpr std::size_t kExamples = 3;

struct Summary {
  nlohmann::json j;
  std::string path;
  bool has(const char* key) const { return j.contains(key) && !j[key].is_null(); }
  double number(const char* key) const {
    if (!j.contains(key) || !j[key].is_number()) throw InputError(fmt::format("{}: no number \"{}\"", path, key));
    return j[key].get<double>();
  }
  template <int D>
  Vec<D> vector(const char* key) const {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != D)
      throw InputError(fmt::format("{}: no {}-vector \"{}\"", path, D, key));
    Vec<D> v;
    for (int a = 0; a < D; ++a) v[a] = j[key][a].get<double>();
    return v;
  }
};

class Checker {
 public:
  explicit Checker(Verification& out) : out_(out) {}
  // Counts a check; when it fails, records the line.
  void check(bool holds, const std::string& violation) {
    ++out_.checks;
    if (!holds) out_.violations.push_back(violation);
  }
  void note(const std::string& why) { out_.notes.push_back(why); }
  Verification& result() { return out_; }
  // |a - b| <= tol * scale.
  void close(const char* what, double a, double b, double scale, double tol) {
    check(std::abs(a - b) <= tol * scale, fmt::format("{}: summary.json says {}, the final state gives {}", what, a, b));
  }

 private:
  Verification& out_;
};

// Rigid bodies (rigid-body engine): each cluster's inertia (Richardson eq. 1) from its
// spheres in one piece, its rotational energy 1/2 omega . I omega (eq. 2) and spin
// angular momentum I omega; the total energy never above the initial one (exactly the
// initial one for elastic, frictionless bounces), and the summary's rotational energy and
// angular momentum as recomputed. `translational` is sum 1/2 M V^2 from final.csv.
template <int D>
void verify_rotation(const Config& cfg, const Box<D>& box, const SphereTable<D>& t, const Summary& summary, double mass,
                     double translational, Checker& c) {
  const int n = static_cast<int>(t.position.size());
  const ClusterPartition clusters = partition_clusters(t.cluster, n);
  const UnwrappedClusters<D> whole = unwrap_clusters(box, t.position, t.radius, clusters);
  double rotational = 0.0;
  Spin<D> momentum = Spin<D>::Zero();  // spin plus orbital about the box centre
  int percolating = 0;
  for (int k = 0; k < clusters.n_clusters(); ++k) {
    if (whole.percolating[k]) { ++percolating; continue; }
    double m = 0.0;
    Vec<D> centre = Vec<D>::Zero();
    for (int i : clusters.members_of(k)) m += t.mass[i], centre += t.mass[i] * whole.position[i];
    centre /= m;
    InertiaTensor<D> inertia = InertiaTensor<D>::Zero();
    for (int i : clusters.members_of(k)) {
      inertia += point_inertia(t.mass[i], Vec<D>(whole.position[i] - centre));
      inertia.diagonal().array() += sphere_moment<D>(t.mass[i], t.radius[i]);
    }
    const int first = clusters.members_of(k).front();
    const Spin<D>& omega = t.spin[first];
    rotational += 0.5 * omega.dot(inertia * omega);
    momentum += inertia * omega + m * cross(Vec<D>(centre - Vec<D>::Constant(0.5 * box.length)), t.velocity[first]);
  }
  if (percolating > 0) {
    c.note(fmt::format("{} cluster(s) wrap around the periodic box: rotational energy and angular momentum not checked",
                       percolating));
    return;
  }
  if (!summary.has("rotational_energy_initial") || !summary.has("rotational_energy_final")) {
    c.note("summary.json has no rotational_energy_initial/final (an older ballagg): the energy budget is not checked");
    return;
  }
  const double e0 = summary.number("kinetic_energy_initial") + summary.number("rotational_energy_initial");
  const double e1 = translational + rotational;
  const double scale = std::max(e0, e1);
  c.close("energy: rotational_energy_final", summary.number("rotational_energy_final"), rotational, scale, verify_tolerance::kSum);
  c.check(e1 <= e0 * (1.0 + verify_tolerance::kBudget),
          fmt::format("energy budget: kinetic energy (translation and rotation) grew from {} to {} (sticking, restitution "
                      "and walls never add energy)", e0, e1));
  const RigidBodyLaw& law = cfg.rigid_body;
  const bool elastic = cfg.collision.outcome == CollisionOutcome::bounce && law.restitution_law == RestitutionLaw::constant &&
                       cfg.collision.restitution == 1.0 && law.mu_t == 0.0 && law.mu_p == 0.0;
  if (elastic)
    c.check(std::abs(e1 - e0) <= verify_tolerance::kBudget * e0,
            fmt::format("energy budget: elastic, frictionless bounces (eps_n = 1, mu = 0) changed the kinetic energy "
                        "from {} to {}", e0, e1));
  // The orbital part needs each body's centre on its unwrapped trajectory, which a
  // periodic box's final.csv folds away; with walls it is the one in the box.
  if (box.periodic()) {
    c.note("periodic box: angular momentum about the box centre is not recomputed (the centres are folded), and not "
           "conserved (collisions across faces and walls exert torques)");
    return;
  }
  const Vec<kSpinDim<D>> l = summary.vector<kSpinDim<D>>("angular_momentum_final");
  const double l_scale = std::sqrt(2.0 * mass * scale) * box.length;
  for (int a = 0; a < kSpinDim<D>; ++a)
    c.close("angular momentum: angular_momentum_final", l[a], momentum[a], l_scale, verify_tolerance::kSum);
}

// A run's final state, read from final.csv, with what the checks below share.
template <int D>
struct FinalState {
  const Config& cfg;
  SphereTable<D> t;
  int n = 0;
  Box<D> box;
  bool ts = false;          // the time-stepping engine: contacts and overlaps within eps_c
  bool coalescing = false;  // sphere coagulation (rigid-body models i-ii) makes one sphere of two
  bool rotating = false;    // rigid-body engine: clusters spin
  double sigma_min = 0.0, r_max = 0.0;
  std::vector<std::int64_t> label;                    // cluster of each sphere
  std::map<std::int64_t, std::vector<int>> members;  // spheres of each cluster

  FinalState(const RunDirectory& run, const Config& config)
      : cfg(config),
        t(read_state_csv<D>(run.path("final.csv"))),
        n(static_cast<int>(t.position.size())),
        box{resolved_box_length(config), config.system.boundary},
        ts(config.engine.kind == EngineKind::ts),
        coalescing(config.engine.kind == EngineKind::rigid_body && config.rigid_body.coagulation == Coagulation::sphere),
        rotating(config.engine.kind == EngineKind::rigid_body) {
    sigma_min = 1e300;
    for (double r : t.radius) {
      sigma_min = std::min(sigma_min, 2.0 * r);
      r_max = std::max(r_max, r);
    }
  }
};

// The number of spheres against summary.json and config.toml.
template <int D>
void verify_counts(const FinalState<D>& s, const Summary& summary, Checker& c) {
  const int n = s.n;
  c.check(n == static_cast<int>(summary.number("n_particles")),
          fmt::format("spheres: final.csv has {}, summary.json n_particles = {}", n, summary.number("n_particles")));
  if (s.cfg.initial.positions != InitialPositions::file && !s.coalescing)
    c.check(n == s.cfg.system.n, fmt::format("spheres: final.csv has {}, config.toml system.n = {}", n, s.cfg.system.n));
  if (s.coalescing)
    c.check(n <= s.cfg.system.n, fmt::format("spheres: final.csv has {}, more than config.toml system.n = {}", n, s.cfg.system.n));
}

// Every centre in the box; with walls, every sphere inside them.
template <int D>
void verify_inside_the_box(const FinalState<D>& s, Checker& c) {
  const SphereTable<D>& t = s.t;
  std::vector<int> outside;
  for (int i = 0; i < s.n; ++i)
    for (int a = 0; a < D; ++a) {
      const double x = t.position[i][a], r = s.box.periodic() ? 0.0 : t.radius[i];
      const double slack = (s.ts ? s.cfg.ts.daha.eps_c : verify_tolerance::kExactContact) * s.sigma_min;
      if (x - r < -slack || x + r > s.box.length + slack) { outside.push_back(i); break; }
    }
  c.check(outside.empty(), fmt::format("box: {} sphere(s) outside [0, {}]{} (first: line {} of final.csv)", outside.size(),
                                       s.box.length, s.box.periodic() ? "" : " or through a wall",
                                       outside.empty() ? 0 : t.line[outside.front()]));
}

// The clusters of final.csv (each sphere its own without a cluster column).
template <int D>
void find_clusters(FinalState<D>& s, Checker& c) {
  s.label = s.t.cluster;
  if (s.label.empty()) {
    c.note("final.csv has no cluster column: cluster checks skipped");
    s.label.resize(s.n);
    for (int i = 0; i < s.n; ++i) s.label[i] = i;
  }
  for (int i = 0; i < s.n; ++i) s.members[s.label[i]].push_back(i);
}

// The clusters' count and largest size against summary.json, and each moving as one body.
template <int D>
void verify_clusters(const FinalState<D>& s, const Summary& summary, Checker& c) {
  const SphereTable<D>& t = s.t;
  std::size_t largest = 0;
  for (const auto& [id, m] : s.members) largest = std::max(largest, m.size());
  c.check(static_cast<double>(s.members.size()) == summary.number("n_clusters"),
          fmt::format("summary: n_clusters = {}, final.csv has {} clusters", summary.number("n_clusters"), s.members.size()));
  c.check(static_cast<double>(largest) == summary.number("largest_cluster"),
          fmt::format("summary: largest_cluster = {}, the largest cluster of final.csv has {} spheres",
                      summary.number("largest_cluster"), largest));
  if (s.rotating)
    c.check(!t.spin.empty(), "rigid bodies: final.csv of a rigid-body run has no spin columns (wx, wy, wz; 2D: wz)");
  // final.csv gives each sphere its body's velocity V and angular velocity omega (the
  // sphere itself moves at V + omega x r): one of each per cluster.
  auto differs = [&](int i, int j) { return t.velocity[i] != t.velocity[j] || (!t.spin.empty() && t.spin[i] != t.spin[j]); };
  std::vector<std::int64_t> nonrigid;
  for (const auto& [id, m] : s.members)
    for (int i : m)
      if (differs(i, m.front())) { nonrigid.push_back(id); break; }
  c.check(nonrigid.empty(), fmt::format("rigid clusters: {} cluster(s) whose spheres move with different velocities{} "
                                        "(first: cluster {})", nonrigid.size(), t.spin.empty() ? "" : " or spins",
                                        nonrigid.empty() ? -1 : nonrigid.front()));
}

struct NearPair {
  int i, j;
  double overlap;  // (sigma - d) / sigma
};

// The pairs near contact, from one scan: those overlapping by more than overlap_tol
// (deepest first), those of one cluster within contact_tol (when `contacts_wanted`), and
// the largest overlap of all (-1e300 with no pair in range).
struct PairFindings {
  std::vector<NearPair> overlapping, contacts;
  double largest_overlap = -1e300;
};

template <int D>
PairFindings scan_pairs(const FinalState<D>& s, double overlap_tol, double contact_tol, bool contacts_wanted) {
  const SphereTable<D>& t = s.t;
  std::vector<std::vector<NearPair>> overlaps(max_threads()), contacts(max_threads());
  std::vector<double> worst(max_threads(), -1e300);
  for_each_pair_within<D>(s.box, t.position, 4.0 * s.r_max, [&](int thread, int i, int j, double d) {
    const double sigma = t.radius[i] + t.radius[j];
    const double overlap = (sigma - d) / sigma;
    worst[thread] = std::max(worst[thread], overlap);
    if (overlap > overlap_tol) overlaps[thread].push_back({std::min(i, j), std::max(i, j), overlap});
    if (contacts_wanted && s.label[i] == s.label[j] && d <= sigma * (1.0 + contact_tol)) contacts[thread].push_back({i, j, overlap});
  });
  PairFindings found;
  for (const auto& v : overlaps) found.overlapping.insert(found.overlapping.end(), v.begin(), v.end());
  std::sort(found.overlapping.begin(), found.overlapping.end(),
            [](const NearPair& a, const NearPair& b) { return a.overlap > b.overlap; });
  for (const auto& v : contacts) found.contacts.insert(found.contacts.end(), v.begin(), v.end());
  found.largest_overlap = *std::max_element(worst.begin(), worst.end());
  return found;
}

// Each cluster one contact graph: its spheres joined by contacts within contact_tol.
template <int D>
void verify_connected(const FinalState<D>& s, const std::vector<NearPair>& contacts, double contact_tol, Checker& c) {
  DisjointSets pieces(s.n);
  for (const NearPair& p : contacts) pieces.unite(p.i, p.j);
  std::vector<std::string> broken;
  int n_broken = 0;
  for (const auto& [id, m] : s.members) {
    int count = 0;
    for (int i : m)
      if (pieces.find(i) == i) ++count;
    if (count > 1 && n_broken++ < static_cast<int>(kExamples))
      broken.push_back(fmt::format("cluster {} ({} spheres) in {} pieces", id, m.size(), count));
  }
  std::string list;
  for (const std::string& b : broken) list += (list.empty() ? "" : "; ") + b;
  c.check(n_broken == 0, fmt::format("connected clusters: {} cluster(s) whose spheres do not form one contact graph at "
                                     "contact tolerance {} ({})", n_broken, contact_tol, list));
}

// No pair overlapping beyond the engine's tolerance, max_overlap as recomputed, and each
// cluster in one piece.
template <int D>
void verify_overlaps_and_contacts(const FinalState<D>& s, const Summary& summary, Checker& c) {
  const SphereTable<D>& t = s.t;
  double stretch = 0.0;
  if (s.ts && summary.has("max_link_stretch")) stretch = summary.number("max_link_stretch");
  double overlap_tol = s.ts ? s.cfg.ts.daha.eps_c : verify_tolerance::kExactContact;
  const double contact_tol = s.ts ? s.cfg.ts.daha.eps_c + stretch : verify_tolerance::kExactContact;
  // The paper's method accepts the iterate of a minimisation that never met (3.28), and
  // merges what its loop leaves in contact where it is: the overlaps it leaves are part of
  // the method, and the run reports them. What the run reports (max_overlap, checked below
  // against the state) is accepted, with a note.
  if (s.ts && s.cfg.ts.method == TsMethod::paper && summary.has("max_overlap") &&
      summary.number("max_overlap") > overlap_tol) {
    overlap_tol = summary.number("max_overlap") * (1.0 + verify_tolerance::kSum);
    c.note(fmt::format("ts.method = \"paper\" left overlaps up to {:.3g} of the contact distance (summary max_overlap, "
                       "minimisations_unconverged = {}): accepted instead of eps_c = {}",
                       summary.number("max_overlap"), summary.number("minimisations_unconverged"), s.cfg.ts.daha.eps_c));
  }
  // Links of the per-sphere models may stretch beyond what a contact graph can follow.
  const bool contacts_checkable = contact_tol <= 1.0;
  const PairFindings found = scan_pairs(s, overlap_tol, contact_tol, contacts_checkable);
  const std::vector<NearPair>& bad = found.overlapping;
  std::string list;
  for (std::size_t k = 0; k < std::min(bad.size(), kExamples); ++k)
    list += fmt::format("{}lines {} and {}: {:.3g}", k ? "; " : "", t.line[bad[k].i], t.line[bad[k].j], bad[k].overlap);
  c.check(bad.empty(), fmt::format("overlap: {} pair(s) overlap by more than {} of their contact distance ({})",
                                   bad.size(), overlap_tol, list));
  if (summary.has("max_overlap") && found.largest_overlap > -1e300)
    c.close("summary: max_overlap", summary.number("max_overlap"), found.largest_overlap, 1.0, verify_tolerance::kSum);
  if (!contacts_checkable)
    c.note(fmt::format("links stretched up to {} sigma (max_link_stretch): connectivity not checked", stretch));
  if (!t.cluster.empty() && contacts_checkable) verify_connected(s, found.contacts, contact_tol, c);
}

// The final momentum against the initial one and the walls' impulse.
template <int D>
void verify_momentum_budget(const FinalState<D>& s, const Summary& summary, const Vec<D>& momentum, double p_scale,
                            Checker& c) {
  const Vec<D> p_final = summary.vector<D>("momentum_final"), p_initial = summary.vector<D>("momentum_initial");
  for (int a = 0; a < D; ++a)
    c.close("momentum: momentum_final", p_final[a], momentum[a], p_scale, verify_tolerance::kSum);
  if (summary.has("wall_impulse")) {
    const Vec<D> walls = summary.vector<D>("wall_impulse");
    if (s.box.periodic())
      c.check(walls == Vec<D>::Zero(), "momentum budget: a periodic box with a wall impulse");
    const Vec<D> missing = momentum - p_initial - walls;
    c.check(missing.norm() <= verify_tolerance::kBudget * p_scale,
            fmt::format("momentum budget: final - initial - wall impulse = ({}), more than {} of sqrt(2 M E)",
                        fmt::join(missing.data(), missing.data() + D, ", "), verify_tolerance::kBudget));
  } else if (s.box.periodic()) {
    const Vec<D> missing = momentum - p_initial;
    c.check(missing.norm() <= verify_tolerance::kBudget * p_scale,
            fmt::format("momentum budget: momentum changed by ({}) in a periodic box",
                        fmt::join(missing.data(), missing.data() + D, ", ")));
  } else {
    c.note("summary.json has no wall_impulse (an older ballagg): the momentum budget with walls is not checked");
  }
}

// Mass, kinetic energy and momentum of final.csv against summary.json, and their budgets.
template <int D>
void verify_budgets(const FinalState<D>& s, const Summary& summary, Checker& c) {
  const SphereTable<D>& t = s.t;
  double mass = 0.0, energy = 0.0;
  Vec<D> momentum = Vec<D>::Zero();
  for (int i = 0; i < s.n; ++i) {
    mass += t.mass[i];
    momentum += t.mass[i] * t.velocity[i];
    energy += 0.5 * t.mass[i] * t.velocity[i].squaredNorm();
  }
  c.close("mass: mass_total", summary.number("mass_total"), mass, mass, verify_tolerance::kSum);
  if (s.cfg.initial.positions != InitialPositions::file && !polydisperse(s.cfg.system) && !s.cfg.system.density)
    c.close("mass: initial mass n * system.mass", static_cast<double>(s.cfg.system.n) * s.cfg.system.mass, mass, mass,
            verify_tolerance::kSum);
  else if (s.cfg.initial.positions != InitialPositions::file)
    c.close("mass: initial mass, the sum over the sampled radii", summarize_sampled_radii(s.cfg).mass, mass, mass,
            verify_tolerance::kSum);
  const double e0 = summary.number("kinetic_energy_initial");
  const double p_scale = std::sqrt(2.0 * mass * std::max(e0, energy));
  c.close("energy: kinetic_energy_final", summary.number("kinetic_energy_final"), energy, std::max(e0, energy),
          verify_tolerance::kSum);
  if (s.coalescing && s.cfg.rigid_body.constant_speed) {
    // Model (i): every merged sphere moves at initial.speed and spins with the pair's
    // angular momentum.
    c.note("collision.constant_speed (model i) conserves neither momentum nor energy by design: budgets not checked");
    return;
  }
  if (s.rotating && !t.spin.empty()) verify_rotation(s.cfg, s.box, t, summary, mass, energy, c);
  else
    c.check(energy <= e0 * (1.0 + verify_tolerance::kBudget),
            fmt::format("energy budget: kinetic energy grew from {} to {} (collisions and walls never add energy)", e0, energy));
  verify_momentum_budget(s, summary, momentum, p_scale, c);
}

template <int D>
void verify_in_dimension(const RunDirectory& run, const Summary& summary, Checker& c) {
  FinalState<D> s(run, run.config);
  verify_counts(s, summary, c);
  if (s.n == 0) return;
  verify_trajectories<D>(run, summary.number("time"), s.coalescing ? 0 : s.n, s.r_max, c.result());
  verify_inside_the_box(s, c);
  find_clusters(s, c);
  verify_clusters(s, summary, c);
  verify_overlaps_and_contacts(s, summary, c);
  verify_budgets(s, summary, c);
}

// The last row of timeseries.csv against the summary: the final state.
void verify_timeseries(const RunDirectory& run, const Summary& summary, Checker& c) {
  std::error_code ec;
  if (!std::filesystem::exists(run.path("timeseries.csv"), ec)) {
    c.note("no timeseries.csv");
    return;
  }
  const std::string text = read_text_file(run.path("timeseries.csv"), "time series", kMaxStateFileBytes);
  CsvReader csv(text, run.path("timeseries.csv"), "(time,clusters,...)");
  CsvRow row, last;
  while (csv.next(row)) last = row;
  auto value = [&](const std::string& name) -> std::optional<double> {
    const int k = csv.column(name);
    if (k < 0 || last.line == 0) return std::nullopt;
    return csv.number(last, k);
  };
  for (auto [column, key] : {std::pair{"time", "time"}, {"clusters", "n_clusters"}, {"largest_cluster", "largest_cluster"},
                             {"events", "events"}}) {
    const std::optional<double> v = value(column);
    c.check(v && *v == summary.number(key), fmt::format("timeseries.csv: last row {} = {}, summary.json {} = {}", column,
                                                        v ? fmt::format("{}", *v) : "missing", key, summary.number(key)));
  }
}

}  // namespace

Verification verify_run(const std::string& dir) {
  const RunDirectory run = open_run_directory(dir);
  Summary summary{nlohmann::json::parse(read_text_file(run.path("summary.json"), "run summary", kMaxSettingsFileBytes), nullptr, false),
                  run.path("summary.json")};
  Verification out;
  Checker c(out);
  if (run.config.system.dimension == 2) verify_in_dimension<2>(run, summary, c);
  else verify_in_dimension<3>(run, summary, c);
  verify_timeseries(run, summary, c);
  return out;
}

}  // namespace ballagg
