#include "ballagg/config/config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <variant>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "ballagg/config/lattice_spacing.hpp"
#include "ballagg/config/radius_section.hpp"
#include "ballagg/config/rigid_body_section.hpp"
#include "ballagg/config/run_continuation.hpp"
#include "ballagg/config/section_reader.hpp"
#include "ballagg/config/set_override.hpp"
#include "ballagg/config/text_file.hpp"
#include "ballagg/config/ts_section.hpp"
#include "ballagg/config/value_ranges.hpp"

namespace ballagg {
namespace {

// x rounded up to three significant digits: a bound to quote that is itself allowed.
double rounded_up(double x) {
  const double unit = std::pow(10.0, std::floor(std::log10(x)) - 2.0);
  return std::ceil(x / unit) * unit;
}

// The box and the skin against the radius (value_ranges.hpp). A state file gives its own
// radii: initial/state_ranges.cpp checks those runs against them.
void check_length_ratios(const Config& c, SectionReader& sys, SectionReader& eng) {
  if (polydisperse(c.system) || c.system.density) return check_sampled_radii(c, sys, eng);
  const double radius = c.system.radius, box = resolved_box_length(c);
  if (c.system.box_length && *c.system.box_length > range::kMaxBoxToRadius * radius)
    sys.refuse("box_length", fmt::format("must be at most {:g} times system.radius = {}: positions at a larger box's "
                                         "scale cannot resolve a contact", range::kMaxBoxToRadius, radius));
  if (c.system.volume_fraction) {
    // The box in radii, (n * unit volume / Vf)^(1/D), without the radius (whose powers
    // could overflow).
    const int d = c.system.dimension;
    const double unit = d == 2 ? std::numbers::pi : 4.0 / 3.0 * std::numbers::pi;
    const double n = static_cast<double>(c.system.n);
    const double radii = std::pow(n * unit / *c.system.volume_fraction, 1.0 / d);
    if (radii > range::kMaxBoxToRadius)
      sys.refuse("volume_fraction",
                 fmt::format("with system.n = {} the box would be {:.3g} radii long, more than the {:g} at which "
                             "positions resolve a contact: must be at least {:.3g} for this n",
                             c.system.n, radii, range::kMaxBoxToRadius,
                             rounded_up(n * unit / std::pow(range::kMaxBoxToRadius, d))));
  }
  if (c.engine.skin) {
    const double lo = range::kMinSkinToRadius * radius, hi = range::kMaxSkinToBox * box;
    if (*c.engine.skin < lo || *c.engine.skin > hi)
      eng.refuse("skin", fmt::format("must be from {} to {} ({:g} times system.radius to {:g} box lengths): a "
                                     "shorter skin is below the resolution of positions, a longer one lists every "
                                     "pair already", lo, hi, range::kMinSkinToRadius, range::kMaxSkinToBox));
  }
}

// Every top-level key of the document must be one of the sections.
void refuse_unknown_sections(const toml::table& root, const std::string& source) {
  static const std::set<std::string> sections{"system", "initial", "collision", "engine", "ts", "stop", "output"};
  for (auto&& [k, node] : root) {
    if (!sections.count(std::string(k.str()))) {
      const std::string where = node.source().begin.line > 0 ? fmt::format("{}:{}", source, node.source().begin.line)
                                                             : "--set " + std::string(k.str());
      if (!node.is_table())
        throw InputError(fmt::format("{}: key '{}' is outside any section (keys belong in the sections system, "
                                     "initial, collision, engine, ts, stop, output)",
                                     where, k.str()));
      throw InputError(fmt::format("{}: unknown section [{}] (sections: system, initial, collision, engine, ts, stop, output)",
                                   where, k.str()));
    }
  }
}

// [system], every key of it checked.
SystemConfig read_system(SectionReader& sys) {
  SystemConfig system_config;
  if (auto v = sys.integer("dimension", 2, 3, "must be 2 or 3")) system_config.dimension = static_cast<int>(*v);
  if (auto v = sys.integer("n", 1, 100'000'000, "must be an integer from 1 to 100000000")) system_config.n = *v;
  system_config.volume_fraction = sys.real("volume_fraction", [](double v) { return v > 0.0 && v < 1.0; },
                                      "must be a number in (0, 1)");
  system_config.box_length = sys.real("box_length", positive, "must be a number > 0");
  refuse_outside(sys, "box_length", system_config.box_length, 0.0, range::kMaxBoxLength,
                 fmt::format("must be at most {:g} ({:g} times the largest radius allowed)", range::kMaxBoxLength,
                             range::kMaxBoxToRadius));
  const auto radius = sys.real("radius", positive, "must be a number > 0");
  refuse_outside(sys, "radius", radius, range::kMinRadius, range::kMaxRadius,
                 fmt::format("must be from {:g} to {:g} (choose units in which radii are near 1)", range::kMinRadius,
                             range::kMaxRadius));
  if (radius) system_config.radius = *radius;
  const auto mass = sys.real("mass", positive, "must be a number > 0");
  refuse_outside(sys, "mass", mass, range::kMinMass, range::kMaxMass,
                 fmt::format("must be from {:g} to {:g} (choose units in which masses are near 1)", range::kMinMass,
                             range::kMaxMass));
  if (mass) system_config.mass = *mass;
  if (auto v = sys.choice("boundary", {"walls", "periodic"})) system_config.boundary = static_cast<Boundary>(*v);
  read_radius_keys(sys, system_config, mass.has_value());
  sys.reject_unknown_keys();
  return system_config;
}

// [initial], every key of it checked.
InitialConfig read_initial(SectionReader& ini) {
  InitialConfig initial_config;
  if (auto v = ini.choice("positions", {"lattice", "random", "file"})) initial_config.positions = static_cast<InitialPositions>(*v);
  if (auto v = ini.choice("velocities", {"fixed-speed", "uniform", "gaussian"}))
    initial_config.velocities = static_cast<InitialVelocities>(*v);
  const auto speed = ini.real("speed", [](double v) { return v >= 0.0; }, "must be a number >= 0");
  refuse_outside(ini, "speed", speed, 0.0, range::kMaxSpeed,
                 fmt::format("must be at most {:g} (choose units in which speeds are near 1)", range::kMaxSpeed));
  if (speed) initial_config.speed = *speed;
  read_lattice_spacing(ini, initial_config);
  if (auto v = ini.string("file", "must be a file name (a string)")) initial_config.file = *v;
  if (auto v = ini.real("time", [](double t) { return t >= 0.0; }, "must be a finite number >= 0 (a simulated time)"))
    initial_config.time = *v;
  if (auto v = ini.boolean("zero_momentum")) initial_config.zero_momentum = *v;
  if (auto v = ini.integer("seed", 0, std::numeric_limits<std::int64_t>::max(), "must be an integer >= 0"))
    initial_config.seed = static_cast<std::uint64_t>(*v);
  ini.reject_unknown_keys();
  return initial_config;
}

// [stop], every key of it checked.
StopConfig read_stop(SectionReader& stop) {
  StopConfig stop_config;
  // The reader refuses values of another type; the range is check_stop_*'s, which
  // Python's Simulation.run applies too.
  const auto any_number = [](double) { return true; };
  if (auto v = stop.integer("clusters", std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max(),
                            std::string(kStopClustersAllowed))) {
    check_stop_clusters(*v, stop.name_of("clusters"));
    stop_config.clusters = *v;
  }
  if (auto v = stop.real("time", any_number, std::string(kStopDurationAllowed), true)) {
    check_stop_duration(*v, stop.name_of("time"));
    stop_config.time = *v;
  }
  if (auto v = stop.real("wall_seconds", any_number, std::string(kStopDurationAllowed), true)) {
    check_stop_duration(*v, stop.name_of("wall_seconds"));
    stop_config.wall_seconds = *v;
  }
  stop_config.aggregated_fraction = stop.real("aggregated_fraction", [](double v) { return v > 0.0 && v <= 1.0; },
                                         "must be a number in (0, 1]");
  stop.reject_unknown_keys();
  return stop_config;
}

// [output], every key of it checked.
OutputConfig read_output(SectionReader& out) {
  OutputConfig output_config;
  if (auto v = out.real("timeseries_interval", [](double x) { return x >= 0.0; }, "must be a number >= 0 (0: none)"))
    output_config.timeseries_interval = *v;
  if (auto v = out.boolean("xyz")) output_config.xyz = *v;
  if (auto v = out.real("snapshot_every", [](double x) { return x >= 0.0; }, "must be a number >= 0 (0: no trajectory)"))
    output_config.snapshot_every = *v;
  if (auto v = out.choices("snapshot_formats", {"h5md", "xyz", "gsd"})) {
    output_config.snapshot_formats.clear();
    for (int k : *v) output_config.snapshot_formats.push_back(static_cast<SnapshotFormat>(k));
  }
  if (auto v = out.choice("snapshot_precision", {"single", "double"}))
    output_config.snapshot_precision = static_cast<SnapshotPrecision>(*v);
  if (auto v = out.boolean("h5md_pad_3d")) output_config.h5md_pad_3d = *v;
  if (auto v = out.real("checkpoint_every", [](double x) { return x >= 0.0; },
                        "must be a number of wall seconds >= 0 (0: checkpoints on SIGINT/SIGTERM only)"))
    output_config.checkpoint_every = *v;
  out.reject_unknown_keys();
  return output_config;
}

// Snapshots need a format; and coalescing spheres leave the run (the number of spheres
// falls), which trajectory.h5md and trajectory.gsd, written with the first frame's number
// of particles and their radii, cannot hold.
void check_snapshot_formats(const Config& c) {
  if (!(c.output.snapshot_every > 0.0)) return;
  if (c.output.snapshot_formats.empty())
    throw InputError(fmt::format("{}: output.snapshot_every = {} but output.snapshot_formats is empty "
                                 "(give \"h5md\", \"xyz\" and/or \"gsd\", or set snapshot_every = 0)",
                                 origin_of(c, {"output.snapshot_every", "output.snapshot_formats"}), c.output.snapshot_every));
  if (c.rigid_body.coagulation != Coagulation::sphere) return;
  for (SnapshotFormat f : c.output.snapshot_formats)
    if (f != SnapshotFormat::xyz)
      throw InputError(fmt::format("{}: output.snapshot_formats = \"{}\" with collision.coagulation = \"sphere\": coalescing "
                                   "spheres change the number and the radii of the spheres, which trajectory.{} keeps "
                                   "fixed; use \"xyz\"",
                                   origin_of(c, {"output.snapshot_formats", "collision.coagulation"}), to_string(f), to_string(f)));
}

// The rules that involve keys of several sections; sets the default volume fraction.
void check_key_combinations(Config& c) {
  const bool from_file = c.initial.positions == InitialPositions::file;
  check_snapshot_formats(c);
  if (c.engine.kind == EngineKind::ts && c.collision.outcome != CollisionOutcome::stick)
    throw InputError(fmt::format("{}: engine.kind = \"ts\" simulates sticking only: collision.outcome must be \"stick\" "
                                 "(use engine.kind = \"ed\" for bounces)", origin_of(c, {"engine.kind", "collision.outcome"})));
  if (c.system.volume_fraction && c.system.box_length)
    throw InputError(fmt::format("{}: give system.volume_fraction or system.box_length, not both",
                                 origin_of(c, {"system.volume_fraction", "system.box_length"})));
  if (from_file && c.initial.file.empty())
    throw InputError(fmt::format("{}: initial.positions = \"file\" needs initial.file",
                                 origin_of(c, {"initial.positions", "initial.file"})));
  if (from_file && !c.system.box_length)
    throw InputError(fmt::format("{}: initial.positions = \"file\" needs system.box_length (a state file gives no box; a "
                                 "run directory as initial.file gives its own)",
                                 origin_of(c, {"initial.positions", "initial.file", "system.volume_fraction"})));
  if (!from_file && !c.initial.file.empty())
    throw InputError(fmt::format("{}: initial.file is only read when initial.positions = \"file\"",
                                 origin_of(c, {"initial.positions", "initial.file"})));
  if (c.stop.time <= c.initial.time)
    throw InputError(fmt::format("{}: stop.time = {} is not after initial.time = {}, the time the initial state is at{}: "
                                 "give a later stop.time", origin_of(c, {"stop.time", "initial.time", "initial.file"}),
                                 c.stop.time, c.initial.time,
                                 c.initial.positions == InitialPositions::file ? fmt::format(" ({})", c.initial.file) : ""));
  if (!from_file && !c.system.box_length && !c.system.volume_fraction && !c.initial.lattice_spacing)
    c.system.volume_fraction = kDefaultVolumeFraction;
  if (c.system.volume_fraction) {
    // Densest packings: hexagonal discs pi / (2 sqrt 3), spheres pi / (3 sqrt 2).
    const double densest = c.system.dimension == 2 ? std::numbers::pi / (2 * std::sqrt(3.0))
                                                   : std::numbers::pi / (3 * std::sqrt(2.0));
    if (*c.system.volume_fraction >= densest)
      throw InputError(fmt::format("{}: system.volume_fraction = {}: no packing of equal {} is that dense (the densest is {:.4f})",
                                   origin_of(c, {"system.volume_fraction", "system.dimension"}),
                                   *c.system.volume_fraction, c.system.dimension == 2 ? "discs" : "spheres", densest));
  }
}

// A relative initial.file written in a configuration file is relative to that file's
// directory (config_dir, given for a file only); one given with --set is relative to the
// working directory.
void locate_initial_file(InitialConfig& initial, const std::optional<std::filesystem::path>& config_dir,
                         const std::set<std::string>& overridden) {
  const std::filesystem::path file(initial.file);
  if (config_dir && !initial.file.empty() && !overridden.count("initial.file") && file.is_relative())
    initial.file = (*config_dir / file).lexically_normal().string();
}

Config read_config(const toml::table& root, const std::string& source, const std::vector<std::string>& overrides,
                   const std::set<std::string>& overridden, const std::optional<std::filesystem::path>& config_dir) {
  refuse_unknown_sections(root, source);
  Config c;
  c.source = source;
  c.set_arguments = overrides;

  SectionReader sys(root, "system", source, overridden);
  c.system = read_system(sys);

  SectionReader ini(root, "initial", source, overridden);
  c.initial = read_initial(ini);
  locate_initial_file(c.initial, config_dir, overridden);

  SectionReader col(root, "collision", source, overridden);
  if (auto v = col.choice("outcome", {"stick", "bounce", "energy-threshold"}))
    c.collision.outcome = static_cast<CollisionOutcome>(*v);
  const auto restitution = col.real("restitution", [](double v) { return v >= 0.0 && v <= 1.0; }, "must be a number in [0, 1]");
  if (restitution) c.collision.restitution = *restitution;
  c.collision.tc_time = col.real("tc_time", [](double v) { return v >= 0.0; }, "must be a number >= 0");
  const std::vector<std::string> rigid_keys = read_rigid_body_keys(col, c.rigid_body);
  col.reject_unknown_keys();

  SectionReader eng(root, "engine", source, overridden);
  if (auto v = eng.choice("kind", {"ed", "ed-naive", "ts", "rigid-body"})) c.engine.kind = static_cast<EngineKind>(*v);
  c.engine.skin = eng.real("skin", positive, "must be a number > 0 (a length)");
  eng.reject_unknown_keys();

  c.ts = read_ts_section(root, source, overridden);

  SectionReader stop(root, "stop", source, overridden);
  c.stop = read_stop(stop);

  SectionReader out(root, "output", source, overridden);
  c.output = read_output(out);

  // Rules that involve several keys.
  continue_from_run_directory(c, sys, ini);
  check_rigid_body_rules(c, rigid_keys, restitution.has_value());
  check_lattice_spacing(c, ini);
  check_key_combinations(c);
  check_radius_key_combinations(c, sys);
  const bool from_file = c.initial.positions == InitialPositions::file;
  if (!from_file) check_length_ratios(c, sys, eng);
  return c;
}

Config parse_root(toml::table root, const std::string& source, const std::vector<std::string>& overrides,
                  const std::optional<std::filesystem::path>& config_dir) {
  std::set<std::string> overridden;
  for (const std::string& o : overrides) apply_override(root, o, overridden);
  return read_config(root, source, overrides, overridden, config_dir);
}

std::string parse_error_message(const toml::parse_error& e, const std::string& source) {
  return fmt::format("{}:{}: invalid TOML: {}", source, e.source().begin.line, e.description());
}

}  // namespace

// toml++ builds a dotted key a.b.c... as nested tables and recurses over them: a key tens
// of thousands of parts deep overflows the stack (found while writing the fuzz targets). A
// ballagg key is SECTION.KEY, so a text with more than kMaxKeyDots dots that can be part of
// a key (not between two digits, as in 0.25) is refused before toml++ reads it. Real
// configurations have a few dozen (comments and paths included).
static constexpr std::size_t kMaxKeyDots = 4096;

void refuse_deeply_dotted_toml(std::string_view text, const std::string& source_name) {
  std::size_t dots = 0;
  auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '.') continue;
    if (i > 0 && i + 1 < text.size() && is_digit(text[i - 1]) && is_digit(text[i + 1])) continue;
    if (++dots > kMaxKeyDots) {
      const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(i), '\n');
      throw InputError(fmt::format("{}:{}: more than {} dotted key parts (ballagg keys are SECTION.KEY)",
                                   source_name, line, kMaxKeyDots));
    }
  }
}

namespace {

Config parse_text(std::string_view text, const std::string& source_name, const std::vector<std::string>& overrides,
                  const std::optional<std::filesystem::path>& config_dir) {
  refuse_deeply_dotted_toml(text, source_name);
  toml::table root;
  try {
    root = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    throw InputError(parse_error_message(e, source_name));
  }
  return parse_root(std::move(root), source_name, overrides, config_dir);
}

}  // namespace

Config parse_config_text(std::string_view text, const std::string& source_name, const std::vector<std::string>& overrides) {
  return parse_text(text, source_name, overrides, std::nullopt);
}

Config load_config(const std::string& path, const std::vector<std::string>& overrides) {
  if (path.empty()) return parse_config_text("", "(defaults)", overrides);
  return parse_text(read_text_file(path, "config file", kMaxSettingsFileBytes), path, overrides,
                    std::filesystem::path(path).parent_path());
}

std::string origin_of(const Config& c, std::initializer_list<std::string_view> keys) {
  std::string origin;
  for (std::size_t k = 0; k < c.set_arguments.size(); ++k) {
    const std::string& argument = c.set_arguments[k];
    const std::string_view key = std::string_view(argument).substr(0, argument.find('='));
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) continue;
    // The last --set of a key is the one that counts.
    const auto later = c.set_arguments.begin() + static_cast<std::ptrdiff_t>(k) + 1;
    const bool set_again = std::any_of(later, c.set_arguments.end(),
                                       [&](const std::string& a) { return a.substr(0, a.find('=')) == key; });
    if (!set_again) origin += (origin.empty() ? "--set " : " --set ") + argument;
  }
  return origin.empty() ? c.source : origin;
}

void check_stop_clusters(std::int64_t clusters, std::string_view name) {
  if (clusters < 1) throw InputError(fmt::format("{} = {}: {}", name, clusters, kStopClustersAllowed));
}

void check_stop_duration(double value, std::string_view name) {
  if (!(value > 0.0)) throw InputError(fmt::format("{} = {}: {}", name, value, kStopDurationAllowed));
}

double resolved_box_length(const Config& c) {
  if (c.system.box_length) return *c.system.box_length;
  if (c.initial.lattice_spacing)
    return static_cast<double>(lattice_side(c.system.n, c.system.dimension)) * *c.initial.lattice_spacing;
  const double n = static_cast<double>(c.system.n), r = c.system.radius;
  const double vf = c.system.volume_fraction.value_or(kDefaultVolumeFraction);
  if (polydisperse(c.system)) {
    const double volume = summarize_sampled_radii(c).volume;
    return c.system.dimension == 2 ? std::sqrt(volume / vf) : std::cbrt(volume / vf);
  }
  if (c.system.dimension == 2) return std::sqrt(n * std::numbers::pi * r * r / vf);
  return std::cbrt(n * 4.0 / 3.0 * std::numbers::pi * r * r * r / vf);
}

std::int64_t lattice_side(std::int64_t n, int dimension) {
  std::int64_t side = 1;
  while (static_cast<std::int64_t>(std::pow(side, dimension) + 0.5) < n) ++side;
  return side;
}

double sphere_mass(const SystemConfig& s, double r) {
  if (s.density) return *s.density * sphere_volume(s.dimension, r);
  if (!polydisperse(s)) return s.mass;
  return s.mass * std::pow(r / s.radius, s.dimension);
}

std::string_view to_string(RadiusLaw l) {
  static constexpr std::string_view names[] = {"monodisperse", "lognormal", "normal", "uniform", "power-law", "discrete"};
  return names[static_cast<int>(l)];
}

std::string_view to_string(InitialPositions p) {
  static constexpr std::string_view names[] = {"lattice", "random", "file"};
  return names[static_cast<int>(p)];
}
std::string_view to_string(InitialVelocities v) {
  static constexpr std::string_view names[] = {"fixed-speed", "uniform", "gaussian"};
  return names[static_cast<int>(v)];
}
std::string_view to_string(EngineKind k) {
  static constexpr std::string_view names[] = {"ed", "ed-naive", "ts", "rigid-body"};
  return names[static_cast<int>(k)];
}
std::string_view to_string(SnapshotFormat f) {
  static constexpr std::string_view names[] = {"h5md", "xyz", "gsd"};
  return names[static_cast<int>(f)];
}
std::string_view to_string(SnapshotPrecision p) { return p == SnapshotPrecision::single ? "single" : "double"; }
std::string_view to_string(TsModel m) {
  static constexpr std::string_view names[] = {"rigid", "almost-rigid", "non-rigid"};
  return names[static_cast<int>(m)];
}
std::string_view to_string(TsDtRule r) { return r == TsDtRule::growth ? "growth" : "adaptive"; }
std::string_view to_string(TsFallBack f) { return f == TsFallBack::retreat ? "retreat" : "keep-flight"; }
std::string_view to_string(TsMethod m) { return m == TsMethod::ours ? "ours" : "paper"; }
std::string_view to_string(CollisionOutcome o) {
  static constexpr std::string_view names[] = {"stick", "bounce", "energy-threshold"};
  return names[static_cast<int>(o)];
}
std::string_view to_string(Coagulation c) { return c == Coagulation::aggregate ? "aggregate" : "sphere"; }
std::string_view to_string(MergedRadius r) { return r == MergedRadius::constant_density ? "constant-density" : "fixed"; }
std::string_view to_string(RestitutionLaw l) { return l == RestitutionLaw::constant ? "constant" : "bridges"; }
std::string_view to_string(Fragmentation f) {
  switch (f) {
    case Fragmentation::off: return "off";
    case Fragmentation::initial_energy: return "initial-energy";
    case Fragmentation::energy: return "energy";
  }
  return "off";
}

}  // namespace ballagg
