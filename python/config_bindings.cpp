// ballagg.Config: from a dict of sections (the keys of docs/configuration.md), from a TOML
// file, or the defaults; every value checked as `ballagg run` checks it.
#include <cmath>

#include <fmt/format.h>

#include "bindings.hpp"
#include "convert.hpp"

namespace ballagg::python {
namespace {

// A Python value as the TOML literal of a --set override.
std::string toml_literal(const py::handle& v, const std::string& key) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
  if (py::isinstance<py::float_>(v)) {
    const double x = v.cast<double>();
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    return py::repr(v).cast<std::string>();  // shortest round trip, '1.0' or '1e-05': TOML floats
  }
  // A JSON string (ASCII, escaped) is a TOML basic string.
  if (py::isinstance<py::str>(v)) return py::module_::import("json").attr("dumps")(v).cast<std::string>();
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::string out = "[";
    for (const py::handle& item : v) out += (out.size() > 1 ? ", " : "") + toml_literal(item, key);
    return out + "]";
  }
  throw py::type_error(fmt::format("config key {}: a {} is not a configuration value", key,
                                   py::str(v.get_type().attr("__name__")).cast<std::string>()));
}

// {"system": {"n": 100}, "ts": {"model": "rigid"}} -> ["system.n=100", "ts.model=\"rigid\""].
void flatten(const py::dict& d, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& [k, v] : d) {
    const std::string key = prefix + py::str(k).cast<std::string>();
    if (py::isinstance<py::dict>(v)) flatten(v.cast<py::dict>(), key + ".", out);
    else out.push_back(key + "=" + toml_literal(v, key));
  }
}

}  // namespace

Config config_from(const py::object& source, const py::object& overrides) {
  std::vector<std::string> sets;
  if (!overrides.is_none()) flatten(overrides.cast<py::dict>(), "", sets);
  if (source.is_none()) return load_config("", sets);
  if (py::isinstance<py::dict>(source)) {
    std::vector<std::string> all;
    flatten(source.cast<py::dict>(), "", all);
    all.insert(all.end(), sets.begin(), sets.end());
    return load_config("", all);
  }
  return load_config(py::str(source).cast<std::string>(), sets);  // a path (str or pathlib.Path)
}

void bind_config(py::module_& m) {
  py::class_<Config>(m, "Config", "A checked run configuration (docs/configuration.md)")
      .def(py::init([](const py::object& source, const py::object& overrides) { return config_from(source, overrides); }),
           py::arg("source") = py::none(), py::arg("overrides") = py::none(),
           "Config(): the defaults; Config({'system': {'n': 400}}): from a dict of sections; Config('run.toml'): "
           "from a TOML file; overrides: a dict applied on top. Bad values raise ballagg.InputError.")
      .def("to_toml", [](const Config& c) { return to_toml_text(c); }, "Every key as TOML (as config.toml)")
      .def("to_dict", [](const Config& c) { return json_loads(to_json_text(c)); }, "Every key as nested dicts")
      .def_property_readonly("dimension", [](const Config& c) { return c.system.dimension; })
      .def_property_readonly("box_length", [](const Config& c) { return resolved_box_length(c); })
      .def("__repr__", [](const Config& c) { return "ballagg.Config(" + py::repr(json_loads(to_json_text(c))).cast<std::string>() + ")"; });
}

}  // namespace ballagg::python
