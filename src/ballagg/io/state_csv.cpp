#include "ballagg/io/state_csv.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "ballagg/config/text_file.hpp"
#include "ballagg/core/input_error.hpp"
#include "ballagg/io/chunked_text.hpp"
#include "ballagg/io/csv_reader.hpp"

namespace ballagg {
namespace {

template <int D>
std::vector<std::string> column_names() {
  if constexpr (D == 2) return {"x", "y", "vx", "vy", "radius", "mass"};
  else return {"x", "y", "z", "vx", "vy", "vz", "radius", "mass"};
}

// The angular velocity of a sphere's cluster (rotating bodies only).
template <int D>
std::vector<std::string> spin_names() {
  if constexpr (D == 2) return {"wz"};
  else return {"wx", "wy", "wz"};
}

// The header's columns: each known, none twice, all required ones present, the spin
// columns all or none. Returns name -> field index.
template <int D>
std::map<std::string, int> state_columns(const CsvReader& csv, const std::string& expected) {
  const std::vector<std::string> required = column_names<D>();
  const std::vector<std::string> spin = spin_names<D>();
  std::map<std::string, int> column;
  const int line_no = csv.header_line();
  for (std::size_t k = 0; k < csv.columns().size(); ++k) {
    const std::string& name = csv.columns()[k];
    const bool known = name == "cluster" || std::find(required.begin(), required.end(), name) != required.end() ||
                       std::find(spin.begin(), spin.end(), name) != spin.end();
    if (!known) {
      const bool other_dim = name == "z" || name == "vz";
      throw InputError(fmt::format("{}:{}: unknown column '{}'{} (expected {})", csv.source(), line_no, name,
                                   other_dim ? " in a 2D run (system.dimension = 2)" : "", expected));
    }
    if (!column.emplace(name, static_cast<int>(k)).second)
      throw InputError(fmt::format("{}:{}: column '{}' appears twice", csv.source(), line_no, name));
  }
  for (const std::string& name : required)
    if (!column.count(name))
      throw InputError(fmt::format("{}:{}: missing column '{}' (expected {})", csv.source(), line_no, name, expected));
  const auto spins = std::count_if(spin.begin(), spin.end(), [&](const std::string& n) { return column.count(n) > 0; });
  if (spins != 0 && spins != static_cast<long>(spin.size()))
    throw InputError(
        fmt::format("{}:{}: give all the spin columns {} or none", csv.source(), line_no, fmt::join(spin, ",")));
  return column;
}

}  // namespace

template <int D>
SphereTable<D> parse_state_csv(const std::string& text, const std::string& source) {
  const std::vector<std::string> spin = spin_names<D>();
  const std::string expected = fmt::format("{},cluster,{} (cluster and spin optional)",
                                           fmt::join(column_names<D>(), ","), fmt::join(spin, ","));
  CsvReader csv(text, source, expected);
  const std::map<std::string, int> column = state_columns<D>(csv, expected);
  SphereTable<D> table;
  table.source = source;
  CsvRow row;
  while (csv.next(row)) {
    auto number = [&](const std::string& name) {
      const double v = csv.number(row, column.at(name));
      if (!std::isfinite(v))
        throw InputError(fmt::format("{}:{}: column {}: {} is not finite", source, row.line, name,
                                     row.fields[column.at(name)]));
      return v;
    };
    Vec<D> x, v;
    static constexpr const char* axes[] = {"x", "y", "z"};
    for (int a = 0; a < D; ++a) {
      x[a] = number(axes[a]);
      v[a] = number(std::string("v") + axes[a]);
    }
    const double radius = number("radius"), mass = number("mass");
    if (radius <= 0.0) throw InputError(fmt::format("{}:{}: radius {} must be > 0", source, row.line, radius));
    if (mass <= 0.0) throw InputError(fmt::format("{}:{}: mass {} must be > 0", source, row.line, mass));
    if (column.count("cluster")) table.cluster.push_back(csv.integer(row, column.at("cluster")));
    if (column.count(spin.front())) {
      Spin<D> w;
      for (int a = 0; a < kSpinDim<D>; ++a) w[a] = number(spin[a]);
      table.spin.push_back(w);
    }
    table.position.push_back(x);
    table.velocity.push_back(v);
    table.radius.push_back(radius);
    table.mass.push_back(mass);
    table.line.push_back(row.line);
  }
  if (table.radius.empty())
    throw InputError(
        fmt::format("{}:{}: no spheres after the header (one line per sphere expected)", source, csv.header_line()));
  return table;
}

template <int D>
SphereTable<D> read_state_csv(const std::string& path) {
  return parse_state_csv<D>(read_text_file(path, "state file", kMaxStateFileBytes), path);
}

template <int D>
void write_state_csv(const State<D>& s, ByteSink& sink) {
  std::vector<int> label(s.clusters.size(), -1);
  int next_label = 0;
  ChunkedText out(sink);
  const bool spinning = !s.spin.empty();
  fmt::format_to(out.out(), "{},cluster{}{}\n", fmt::join(column_names<D>(), ","), spinning ? "," : "",
                 spinning ? fmt::format("{}", fmt::join(spin_names<D>(), ",")) : std::string());
  for (int i = 0; i < s.n_spheres(); ++i) {
    const Vec<D> x = s.position(i, s.time);
    const Vec<D>& v = s.velocity(i);
    for (int a = 0; a < D; ++a) fmt::format_to(out.out(), "{},", x[a]);
    for (int a = 0; a < D; ++a) fmt::format_to(out.out(), "{},", v[a]);
    int& l = label[s.spheres.cluster[i]];
    if (l < 0) l = next_label++;
    fmt::format_to(out.out(), "{},{},{}", s.spheres.radius[i], s.spheres.mass[i], l);
    if (spinning) {
      const Spin<D>& w = s.spin[s.spheres.cluster[i]].angular_velocity;
      for (int a = 0; a < kSpinDim<D>; ++a) fmt::format_to(out.out(), ",{}", w[a]);
    }
    out.push_back('\n');
    out.end_line();
  }
  out.flush();
}

template <int D>
std::string state_csv_text(const State<D>& s) {
  std::string text;
  StringSink sink(text);
  write_state_csv(s, sink);
  return text;
}

template SphereTable<2> read_state_csv<2>(const std::string&);
template SphereTable<3> read_state_csv<3>(const std::string&);
template SphereTable<2> parse_state_csv<2>(const std::string&, const std::string&);
template SphereTable<3> parse_state_csv<3>(const std::string&, const std::string&);
template std::string state_csv_text<2>(const State<2>&);
template std::string state_csv_text<3>(const State<3>&);
template void write_state_csv<2>(const State<2>&, ByteSink&);
template void write_state_csv<3>(const State<3>&, ByteSink&);

}  // namespace ballagg
