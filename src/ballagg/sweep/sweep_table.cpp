#include "ballagg/sweep/sweep_table.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "ballagg/config/text_file.hpp"
#include "ballagg/io/csv_reader.hpp"
#include "ballagg/io/output_dir.hpp"

namespace ballagg {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// An indicator of one run: its column name and where it is read.
struct Indicator {
  std::string name;
  const char* file;                 // "summary" or "analysis"
  std::vector<std::string> path;    // keys into the JSON; an integer key indexes an array
  bool absolute = false;            // |value| (orientation: an axis has no sign)
};

std::vector<Indicator> indicators(int dimension) {
  std::vector<Indicator> list = {
      {"wall_seconds", "summary", {"wall_seconds"}},
      {"simulated_time", "summary", {"time"}},
      {"events", "summary", {"events"}},
      {"n_clusters", "summary", {"n_clusters"}},
      {"largest_cluster", "summary", {"largest_cluster"}},
      {"max_overlap", "summary", {"max_overlap"}},
      {"contacts", "analysis", {"all_spheres", "contacts"}},
      {"contacts_with_self", "analysis", {"all_spheres", "contacts_with_self"}},
      {"box_counting_dimension", "analysis", {"all_spheres", "box_counting", "dimension"}},
      {"box_counting_dimension_error", "analysis", {"all_spheres", "box_counting", "dimension_error"}},
      {"box_counting_prefactor", "analysis", {"all_spheres", "box_counting", "prefactor"}},
      {"correlation_dimension", "analysis", {"all_spheres", "correlation_dimension"}},
      {"largest_contacts", "analysis", {"largest_cluster", "contacts"}},
      {"largest_box_counting_dimension", "analysis", {"largest_cluster", "box_counting", "dimension"}},
      {"largest_mass_radius_dimension", "analysis", {"largest_cluster", "mass_radius_dimension"}},
      {"largest_correlation_dimension", "analysis", {"largest_cluster", "correlation_dimension"}},
      {"largest_radius_of_gyration", "analysis", {"largest_cluster", "radius_of_gyration"}},
      {"largest_r_max", "analysis", {"largest_cluster", "r_max"}},
      {"largest_density", "analysis", {"largest_cluster", "density"}},
      {"largest_aspect_ratio", "analysis", {"largest_cluster", "aspect_ratio"}},
  };
  static constexpr const char* axes[] = {"x", "y", "z"};
  for (int a = 0; a < dimension; ++a)
    list.push_back({fmt::format("largest_orientation_{}_abs", axes[a]), "analysis",
                    {"largest_cluster", "orientation", std::to_string(a)}, true});
  list.push_back({"population_dimension", "analysis", {"population", "dimension_from_density"}});
  return list;
}

double lookup(const Json& j, const Indicator& ind) {
  const Json* node = &j;
  for (const std::string& key : ind.path) {
    if (node->is_array()) {
      const std::size_t k = std::stoul(key);
      if (k >= node->size()) return kNaN;
      node = &(*node)[k];
    } else if (node->is_object() && node->contains(key)) {
      node = &(*node)[key];
    } else {
      return kNaN;
    }
  }
  if (!node->is_number()) return kNaN;  // null: undefined for this run
  const double v = node->get<double>();
  return ind.absolute ? std::abs(v) : v;
}

// A CSV table of numbers with a header line (the analysis tables).
struct NumericTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  int column(const std::string& name) const {
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (columns[k] == name) return static_cast<int>(k);
    return -1;
  }
};

// A run's files are read only when they are regular files: anything else (a FIFO, a
// device) would never end; such a file counts as missing.
bool readable_file(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

// A run's analysis table, read strictly (io/csv_reader.hpp): a field that is not a number
// is an error naming the file and line, never a 0 in the sweep's tables.
std::optional<NumericTable> read_numeric_csv(const fs::path& path) {
  if (!readable_file(path)) return std::nullopt;
  const std::string text = read_text_file(path.string(), "analysis table", kMaxStateFileBytes);
  CsvReader csv(text, path.string(), "(a header line of column names)");
  NumericTable t;
  t.columns = csv.columns();
  CsvRow row;
  while (csv.next(row)) {
    std::vector<double> values;
    for (int k = 0; k < static_cast<int>(row.fields.size()); ++k) values.push_back(csv.number(row, k));
    t.rows.push_back(std::move(values));
  }
  return t;
}

std::optional<Json> read_json(const fs::path& path) {
  if (!readable_file(path)) return std::nullopt;
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    return Json::parse(in);
  } catch (const Json::exception&) {
    return std::nullopt;
  }
}

std::string num(double v) { return std::isnan(v) ? "nan" : fmt::format("{}", v); }

// CSV field: quoted when it holds a comma or a quote.
std::string field(const std::string& s) {
  if (s.find_first_of(",\"") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string unquoted(const std::string& toml_value) {
  if (toml_value.size() >= 2 && toml_value.front() == '"') return toml_value.substr(1, toml_value.size() - 2);
  return toml_value;
}

std::string method_of(const Config& c) {
  if (c.engine.kind != EngineKind::ts) return std::string(to_string(c.engine.kind));
  return "ts-" + std::string(to_string(c.ts.model));
}

double volume_fraction_of(const Config& c) {
  if (c.system.volume_fraction) return *c.system.volume_fraction;  // as given, without round-off
  const double l = resolved_box_length(c), r = c.system.radius, n = static_cast<double>(c.system.n);
  if (polydisperse(c.system)) return summarize_sampled_radii(c).volume / std::pow(l, c.system.dimension);
  const double sphere = c.system.dimension == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return n * sphere / std::pow(l, c.system.dimension);
}

// Mean and error of column `name` of a curve table over the runs, row by row.
void curve_rows(fmt::memory_buffer& out, int point, const std::vector<NumericTable>& tables,
                const std::vector<std::string>& keys, const std::vector<std::string>& values) {
  if (tables.empty()) return;
  const NumericTable& first = tables.front();
  for (std::size_t row = 0; row < first.rows.size(); ++row) {
    fmt::format_to(std::back_inserter(out), "{}", point);
    for (const std::string& k : keys) fmt::format_to(std::back_inserter(out), ",{}", num(first.rows[row][first.column(k)]));
    for (const std::string& v : values) {
      std::vector<double> xs;
      for (const NumericTable& t : tables)
        if (row < t.rows.size() && t.column(v) >= 0) xs.push_back(t.rows[row][t.column(v)]);
      const MeanAndError m = mean_and_error(xs);
      fmt::format_to(std::back_inserter(out), ",{},{}", num(m.mean), num(m.error));
    }
    fmt::format_to(std::back_inserter(out), "\n");
  }
}

}  // namespace

MeanAndError mean_and_error(const std::vector<double>& values) {
  MeanAndError m;
  double sum = 0.0;
  for (double v : values)
    if (std::isfinite(v)) sum += v, ++m.count;
  if (m.count == 0) return {kNaN, kNaN, 0};
  m.mean = sum / m.count;
  if (m.count < 2) {
    m.error = kNaN;
    return m;
  }
  double squares = 0.0;
  for (double v : values)
    if (std::isfinite(v)) squares += (v - m.mean) * (v - m.mean);
  m.error = std::sqrt(squares / (static_cast<double>(m.count) * (m.count - 1)));
  return m;
}

namespace {

// What the finished runs hold, per point: the indicator values of the runs in the means,
// their curve tables, the runs cut by a resource limit; and runs.csv.
struct RunsRead {
  std::map<int, std::vector<std::vector<double>>> values;
  std::map<int, std::vector<NumericTable>> box_tables, pair_tables;
  std::map<int, int> cut;
  fmt::memory_buffer runs_csv;
};

// runs.csv's first columns: the point, its variant (when the sweep file has [[variants]])
// and its value of each grid key, then the run.
void runs_csv_header(fmt::memory_buffer& out, const SweepSpec& spec, const std::vector<Indicator>& list) {
  fmt::format_to(std::back_inserter(out), "point");
  if (has_variants(spec)) fmt::format_to(std::back_inserter(out), ",variant");
  for (const SweepAxis& a : spec.axes) fmt::format_to(std::back_inserter(out), ",{}", field(a.key));
  fmt::format_to(std::back_inserter(out), ",realization,seed,run,stop_reason");
  for (const Indicator& ind : list) fmt::format_to(std::back_inserter(out), ",{}", ind.name);
  fmt::format_to(std::back_inserter(out), "\n");
}

void runs_csv_row(fmt::memory_buffer& out, const SweepSpec& spec, const SweepPoint& p, const SweepRun& r,
                  const std::string& reason, const std::vector<double>& row) {
  fmt::format_to(std::back_inserter(out), "{}", r.point);
  if (has_variants(spec)) fmt::format_to(std::back_inserter(out), ",{}", field(p.variant->label));
  for (const SweepSetting* s : p.values) fmt::format_to(std::back_inserter(out), ",{}", field(unquoted(s->value)));
  fmt::format_to(std::back_inserter(out), ",{},{},{},{}", r.realization, r.seed, r.name, reason);
  for (double v : row) fmt::format_to(std::back_inserter(out), ",{}", num(v));
  fmt::format_to(std::back_inserter(out), "\n");
}

RunsRead read_runs(const std::string& out_dir, const SweepSpec& spec, const std::vector<SweepPoint>& points,
                   const std::vector<SweepRun>& runs, const std::vector<Indicator>& list) {
  RunsRead read;
  runs_csv_header(read.runs_csv, spec, list);
  for (const SweepRun& r : runs) {
    const fs::path dir = fs::path(out_dir) / "runs" / r.name;
    const std::optional<Json> summary = read_json(dir / "summary.json");
    const std::optional<Json> analysis = read_json(dir / "analysis.json");
    if (!summary || !analysis) continue;
    std::vector<double> row;
    for (const Indicator& ind : list) row.push_back(lookup(std::string(ind.file) == "summary" ? *summary : *analysis, ind));
    const std::string reason = summary->value("stop_reason", std::string());
    runs_csv_row(read.runs_csv, spec, points[r.point], r, reason, row);
    // A run stopped by stop.wall_seconds or an output cap (resource limits, not criteria of
    // the state the sweep asks for) did not reach that state: listed in runs.csv, left out
    // of the means.
    if (reason == "wall_seconds" || reason == "output_limit") {
      ++read.cut[r.point];
      continue;
    }
    read.values[r.point].push_back(std::move(row));
    if (auto t = read_numeric_csv(dir / "box_counting.csv")) read.box_tables[r.point].push_back(std::move(*t));
    if (auto t = read_numeric_csv(dir / "pair_distribution.csv")) read.pair_tables[r.point].push_back(std::move(*t));
  }
  return read;
}

// sweep.csv's row of one point: its identity, its configuration, then mean and error of
// each indicator.
void sweep_csv_row(fmt::memory_buffer& table, const SweepPoint& p, const Config& c, const RunsRead& read,
                   std::size_t indicators) {
  fmt::format_to(std::back_inserter(table), "{},{}", p.index, field(p.variant->label));
  for (const SweepSetting* s : p.values) fmt::format_to(std::back_inserter(table), ",{}", field(unquoted(s->value)));
  static const std::vector<std::vector<double>> none;
  const auto found = read.values.find(p.index);
  const std::vector<std::vector<double>>& v = found != read.values.end() ? found->second : none;
  const auto cut = read.cut.find(p.index);
  fmt::format_to(std::back_inserter(table), ",{},{},{},{},{},{},{},{}", method_of(c), c.system.dimension, c.system.n,
                 num(volume_fraction_of(c)), num(resolved_box_length(c)),
                 c.engine.kind == EngineKind::ts ? num(c.ts.dt_factor) : "nan", v.size(),
                 cut != read.cut.end() ? cut->second : 0);
  for (std::size_t k = 0; k < indicators; ++k) {
    std::vector<double> xs;
    for (const std::vector<double>& row : v) xs.push_back(row[k]);
    const MeanAndError m = mean_and_error(xs);
    fmt::format_to(std::back_inserter(table), ",{},{}", num(m.mean), num(m.error));
  }
  fmt::format_to(std::back_inserter(table), "\n");
}

}  // namespace

void write_sweep_tables(const std::string& out_dir, const SweepSpec& spec, const std::vector<SweepPoint>& points,
                        const std::vector<SweepRun>& runs) {
  const int dimension = runs.empty() ? 2 : runs.front().config.system.dimension;
  const std::vector<Indicator> list = indicators(dimension);
  RunsRead read = read_runs(out_dir, spec, points, runs, list);
  std::map<int, const Config*> point_config;
  for (const SweepRun& r : runs) point_config.emplace(r.point, &r.config);

  fmt::memory_buffer table;
  fmt::format_to(std::back_inserter(table), "point,variant");
  for (const SweepAxis& a : spec.axes) fmt::format_to(std::back_inserter(table), ",{}", field(a.key));
  fmt::format_to(std::back_inserter(table), ",method,dimension,n,volume_fraction,box_length,dt_factor,runs,runs_cut");
  for (const Indicator& ind : list) fmt::format_to(std::back_inserter(table), ",{}_mean,{}_sem", ind.name, ind.name);
  fmt::format_to(std::back_inserter(table), "\n");
  fmt::memory_buffer boxes, pairs;
  fmt::format_to(std::back_inserter(boxes), "point,level,eps,fitted,boxes_all_mean,boxes_all_sem,boxes_largest_mean,boxes_largest_sem\n");
  fmt::format_to(std::back_inserter(pairs), "point,r_over_R,P_all_mean,P_all_sem,P_largest_mean,P_largest_sem\n");
  for (const SweepPoint& p : points) {
    sweep_csv_row(table, p, *point_config.at(p.index), read, list.size());
    curve_rows(boxes, p.index, read.box_tables[p.index], {"level", "eps", "fitted"}, {"boxes_all", "boxes_largest"});
    curve_rows(pairs, p.index, read.pair_tables[p.index], {"r_over_R"}, {"P_all", "P_largest"});
  }
  write_file_atomically(out_dir, "runs.csv", fmt::to_string(read.runs_csv));
  write_file_atomically(out_dir, "sweep_box_counting.csv", fmt::to_string(boxes));
  write_file_atomically(out_dir, "sweep_pair_distribution.csv", fmt::to_string(pairs));
  write_file_atomically(out_dir, "sweep.csv", fmt::to_string(table));
}

}  // namespace ballagg
