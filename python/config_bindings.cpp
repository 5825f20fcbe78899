// ballagg.Config: from a dict of sections (the keys of docs/configuration.md), from a TOML
// file, or the defaults; every value checked as `ballagg run` checks it.
#include <cmath>

#include <fmt/format.h>

#include "bindings.hpp"
#include "convert.hpp"

namespace ballagg::python {
namespace {

// A key given in Python: its dotted name, its TOML literal, and whether the value was a
// float (an integer key refuses one, below).
struct GivenKey {
  std::string name, literal;
  bool is_float = false;
};

std::string type_name(const py::handle& v) { return py::str(v.get_type().attr("__name__")).cast<std::string>(); }

// A Python value as the TOML literal of a --set override: bool, int, float, str, list or
// tuple, and numpy's scalars (numpy.int64, numpy.float32, numpy.bool_, ...) and arrays.
std::string toml_literal(const py::handle& v, const std::string& key) {
  const py::module_ numbers = py::module_::import("numbers"), np = py::module_::import("numpy");
  if (py::isinstance<py::bool_>(v) || py::isinstance(v, np.attr("bool_"))) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance(v, numbers.attr("Integral"))) return py::str(py::int_(py::reinterpret_borrow<py::object>(v))).cast<std::string>();
  if (py::isinstance(v, numbers.attr("Real"))) {
    const double x = py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>();
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    return py::repr(py::float_(x)).cast<std::string>();  // shortest round trip, '1.0' or '1e-05': TOML floats
  }
  // A JSON string (ASCII, escaped) is a TOML basic string.
  if (py::isinstance<py::str>(v)) return py::module_::import("json").attr("dumps")(v).cast<std::string>();
  if (py::isinstance(v, np.attr("ndarray"))) return toml_literal(v.attr("tolist")(), key);
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::string out = "[";
    for (const py::handle& item : v) out += (out.size() > 1 ? ", " : "") + toml_literal(item, key);
    return out + "]";
  }
  throw py::type_error(fmt::format("{}: a {} is not a configuration value (a bool, int, float, str or list)", key,
                                   type_name(v)));
}

bool is_float(const py::handle& v) {
  const py::module_ numbers = py::module_::import("numbers");
  return py::isinstance(v, numbers.attr("Real")) && !py::isinstance(v, numbers.attr("Integral"));
}

// {"system": {"n": 100}, "ts": {"model": "rigid"}} -> system.n = 100, ts.model = "rigid".
void flatten(const py::dict& sections, std::vector<GivenKey>& out) {
  for (const auto& [section, keys] : sections) {
    const std::string name = py::str(section).cast<std::string>();
    if (!py::isinstance<py::dict>(keys))
      throw py::type_error(fmt::format("{}: a {} where a section's dict of keys belongs (for example {{'system': "
                                       "{{'n': 400}}}})", name, type_name(keys)));
    for (const auto& [k, v] : keys.cast<py::dict>()) {
      const std::string key = name + "." + py::str(k).cast<std::string>();
      if (py::isinstance<py::dict>(v))
        throw py::type_error(fmt::format("{}: a dict where a value belongs (keys are section.key, for example "
                                         "{{'system': {{'n': 400}}}})", key));
      out.push_back({key, toml_literal(v, key), is_float(v)});
    }
  }
}

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

// The configuration reader names an override by its --set argument; a key given in
// Python is named by itself: "--set system.n: system.n = -3: ..." -> "system.n = -3: ...".
std::string python_message(std::string message, const std::vector<GivenKey>& keys) {
  for (const GivenKey& k : keys) {
    const std::string section = k.name.substr(0, k.name.find('.'));
    replace_all(message, "--set " + k.name + ": " + k.name + " ", k.name + " ");
    replace_all(message, "--set " + k.name, k.name);
    replace_all(message, "--set " + section + ":", section + ":");  // an unknown section
  }
  return message;
}

// TOML reads 100.0 as the integer 100 for an integer key, as the command line does; Python
// tells int from float, so a float given for an integer key (system.n = 100.0) is refused.
void refuse_floats_for_integers(const Config& c, const std::vector<GivenKey>& keys) {
  const py::dict resolved = json_loads(to_json_text(c));
  for (const GivenKey& k : keys) {
    if (!k.is_float) continue;
    const std::size_t dot = k.name.find('.');
    const py::object section = resolved.attr("get")(k.name.substr(0, dot));
    if (section.is_none()) continue;
    const py::object value = section.attr("get")(k.name.substr(dot + 1));
    if (py::isinstance<py::int_>(value) && !py::isinstance<py::bool_>(value))
      throw InputError(fmt::format("{} = {}: must be an integer (a Python int or a numpy integer), not a float",
                                   k.name, k.literal));
  }
}

Config load_checked(const std::string& path, const std::vector<GivenKey>& keys) {
  std::vector<std::string> sets;
  for (const GivenKey& k : keys) sets.push_back(k.name + "=" + k.literal);
  Config c;
  try {
    c = load_config(path, sets);
  } catch (const InputError& e) {
    throw InputError(python_message(e.what(), keys));
  }
  refuse_floats_for_integers(c, keys);
  return c;
}

}  // namespace

Config config_from(const py::object& source, const py::object& overrides) {
  std::vector<GivenKey> keys;
  const bool is_dict = py::isinstance<py::dict>(source);
  if (is_dict) flatten(source.cast<py::dict>(), keys);
  if (!overrides.is_none()) flatten(overrides.cast<py::dict>(), keys);
  if (source.is_none() || is_dict) return load_checked("", keys);
  return load_checked(py::str(source).cast<std::string>(), keys);  // a path (str or pathlib.Path)
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
