// The analysis as `ballagg analyze` writes it: analysis.json (one schema for the command
// line and Python, produced by the same function, io/analysis_files.hpp) and the CSV tables
// as columns of numpy arrays.
#include <charconv>
#include <map>

#include "analysis_convert.hpp"

#include "ballagg/io/analysis_files.hpp"
#include "ballagg/io/csv_reader.hpp"

namespace ballagg::python {
namespace {

bool all_parse(const std::vector<std::string>& fields, auto parse) {
  for (const std::string& f : fields)
    if (!parse(f)) return false;
  return true;
}

// One column: int64 when every field is an integer, float64 when every field is a number
// ("nan" included), otherwise strings (the fit-flaw codes).
py::object column_array(const std::vector<std::string>& fields) {
  const auto is_integer = [](const std::string& f) {
    long long v = 0;
    const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
    return ec == std::errc() && end == f.data() + f.size();
  };
  const auto is_number = [](const std::string& f) {
    double v = 0;
    const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
    return ec == std::errc() && end == f.data() + f.size();
  };
  py::module_ np = py::module_::import("numpy");
  if (all_parse(fields, is_integer)) {
    std::vector<std::int64_t> v;
    for (const std::string& f : fields) v.push_back(std::stoll(f));
    return from_vector(v);
  }
  if (all_parse(fields, is_number)) {
    std::vector<double> v;
    for (const std::string& f : fields) {
      double x = 0;
      std::from_chars(f.data(), f.data() + f.size(), x);
      v.push_back(x);
    }
    return from_vector(v);
  }
  return np.attr("array")(py::cast(fields));
}

// A CSV table of `ballagg analyze` as {column name: array}, columns in file order.
py::dict csv_columns(const std::string& text, const std::string& name) {
  CsvReader reader(text, name, "");
  std::vector<std::vector<std::string>> fields(reader.columns().size());
  for (CsvRow row; reader.next(row);)
    for (std::size_t k = 0; k < fields.size(); ++k) fields[k].emplace_back(row.fields[k]);
  py::dict d;
  for (std::size_t k = 0; k < fields.size(); ++k) d[py::str(reader.columns()[k])] = column_array(fields[k]);
  return d;
}

}  // namespace

template <int D>
py::object aggregate_analysis(const Box<D>& box, const SphereTable<D>& spheres, const py::object& state_file,
                              bool tables) {
  const std::string file = state_file.is_none() ? std::string() : py::str(state_file).cast<std::string>();
  const std::map<std::string, std::string> files = analysis_files(analyze_aggregates(box, spheres), file);
  py::dict analysis = json_loads(files.at("analysis.json"));
  analysis["state_file"] = state_file;
  if (!tables) return analysis;
  py::dict columns;
  for (const auto& [name, text] : files) {
    const std::string stem = name.substr(0, name.rfind('.'));
    if (name.ends_with(".csv")) columns[py::str(stem)] = csv_columns(text, name);
  }
  return py::make_tuple(analysis, columns);
}

template py::object aggregate_analysis<2>(const Box<2>&, const SphereTable<2>&, const py::object&, bool);
template py::object aggregate_analysis<3>(const Box<3>&, const SphereTable<3>&, const py::object&, bool);

}  // namespace ballagg::python
