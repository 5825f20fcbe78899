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

#include "ballagg/config/text_file.hpp"
#include "ballagg/config/value_ranges.hpp"

namespace ballagg {
namespace {

// Reads one section of the TOML document, remembering which keys it was asked for so
// that anything else is reported as unknown. Every error names where the value came from.
class SectionReader {
 public:
  SectionReader(const toml::table& root, std::string section, const std::string& source,
                const std::set<std::string>& overridden)
      : section_(std::move(section)), source_(source), overridden_(overridden) {
    if (const toml::node* node = root.get(section_)) {
      table_ = node->as_table();
      if (table_ == nullptr) {
        const std::string where = node->source().begin.line > 0
                                      ? fmt::format("{}:{}", source_, node->source().begin.line)
                                      : source_;
        std::ostringstream type;
        type << node->type();
        throw InputError(fmt::format("{}: {} must be a section ([{}]), but it is a value of type {}", where,
                                     section_, section_, type.str()));
      }
    }
  }

  std::optional<std::int64_t> integer(const std::string& key, std::int64_t lo, std::int64_t hi,
                                      const std::string& allowed) {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    std::optional<std::int64_t> v;
    if (auto i = node->value_exact<std::int64_t>()) v = *i;
    else if (auto d = node->value_exact<double>(); d && std::isfinite(*d) && *d == std::floor(*d) && std::abs(*d) < 9e18)
      v = static_cast<std::int64_t>(*d);  // 1e4 from the command line is an integer
    if (!v || *v < lo || *v > hi) fail(*node, key, allowed);
    return v;
  }

  // A finite number (or +inf when allow_infinite) accepted by `ok`.
  std::optional<double> real(const std::string& key, const std::function<bool(double)>& ok,
                             const std::string& allowed, bool allow_infinite = false) {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    std::optional<double> v;
    if (auto d = node->value_exact<double>()) v = *d;
    else if (auto i = node->value_exact<std::int64_t>()) v = static_cast<double>(*i);
    if (!v || std::isnan(*v) || (std::isinf(*v) && !(allow_infinite && *v > 0)) || !ok(*v))
      fail(*node, key, allowed);
    return v;
  }

  std::optional<bool> boolean(const std::string& key) {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    auto b = node->value_exact<bool>();
    if (!b) fail(*node, key, "must be true or false");
    return b;
  }

  std::optional<std::string> string(const std::string& key, const std::string& allowed) {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    auto s = node->value_exact<std::string>();
    if (!s) fail(*node, key, allowed);
    return s;
  }

  // One of `names`; returns its index.
  std::optional<int> choice(const std::string& key, const std::vector<std::string>& names) {
    std::string allowed = "must be one of";
    for (std::size_t k = 0; k < names.size(); ++k) allowed += (k ? ", \"" : " \"") + names[k] + "\"";
    auto s = string(key, allowed);
    if (!s) return std::nullopt;
    for (std::size_t k = 0; k < names.size(); ++k)
      if (*s == names[k]) return static_cast<int>(k);
    fail(*find(key), key, allowed);
  }

  // A list of distinct names from `names` (a TOML array, or one string for a list of one);
  // returns their indices in the order given.
  std::optional<std::vector<int>> choices(const std::string& key, const std::vector<std::string>& names) {
    std::string allowed = "must be a list of distinct names from";
    for (std::size_t k = 0; k < names.size(); ++k) allowed += (k ? ", \"" : " \"") + names[k] + "\"";
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    std::vector<const toml::node*> items;
    if (const toml::array* a = node->as_array()) {
      for (const toml::node& item : *a) items.push_back(&item);
    } else {
      items.push_back(node);
    }
    std::vector<int> picked;
    for (const toml::node* item : items) {
      auto s = item->value_exact<std::string>();
      const auto it = s ? std::find(names.begin(), names.end(), *s) : names.end();
      const int index = static_cast<int>(it - names.begin());
      if (it == names.end() || std::find(picked.begin(), picked.end(), index) != picked.end()) fail(*node, key, allowed);
      picked.push_back(index);
    }
    return picked;
  }

  // Reports the first key of the section that nobody asked for.
  void reject_unknown_keys() const {
    if (table_ == nullptr) return;
    for (auto&& [k, node] : *table_) {
      const std::string key(k.str());
      if (!known_.count(key)) {
        std::string allowed;
        for (const std::string& a : known_) allowed += (allowed.empty() ? "" : ", ") + a;
        throw InputError(fmt::format("{}: unknown key '{}.{}' (keys of [{}]: {})", where(node, key), section_,
                                     key, section_, allowed));
      }
    }
  }

  // Refuses the value given for `key` (a rule that involves other keys too).
  [[noreturn]] void refuse(const std::string& key, const std::string& allowed) { fail(*find(key), key, allowed); }

  [[noreturn]] void fail(const toml::node& node, const std::string& key, const std::string& allowed) const {
    std::ostringstream value;
    if (node.is_string()) value << '"' << *node.value<std::string>() << '"';
    else if (auto d = node.value_exact<double>()) value << fmt::format("{}", *d);  // shortest form: 1e-09
    else if (const toml::array* a = node.as_array()) {
      value << '[';
      for (std::size_t k = 0; k < a->size(); ++k) {
        const toml::node& item = *a->get(k);
        value << (k ? ", " : "");
        if (item.is_string()) value << '"' << *item.value<std::string>() << '"';
        else if (item.is_value()) item.visit([&](auto&& v) { value << v; });
        else value << "<" << item.type() << ">";
      }
      value << ']';
    }
    else if (node.is_value()) node.visit([&](auto&& v) { value << v; });
    else value << "<" << node.type() << ">";
    throw InputError(fmt::format("{}: {}.{} = {}: {}", where(node, key), section_, key, value.str(), allowed));
  }

  // "<where>: section.key", the name an error about the value of key gives it.
  std::string name_of(const std::string& key) {
    const toml::node* node = find(key);
    return node == nullptr ? section_ + "." + key : fmt::format("{}: {}.{}", where(*node, key), section_, key);
  }

  std::string where(const toml::node& node, const std::string& key) const {
    if (overridden_.count(section_ + "." + key)) return "--set " + section_ + "." + key;
    if (node.source().begin.line > 0) return fmt::format("{}:{}", source_, node.source().begin.line);
    return source_;
  }

 private:
  const toml::node* find(const std::string& key) {
    known_.insert(key);
    return table_ == nullptr ? nullptr : table_->get(key);
  }

  std::string section_;
  const std::string& source_;
  const std::set<std::string>& overridden_;
  const toml::table* table_ = nullptr;
  std::set<std::string> known_;
};

auto positive = [](double v) { return v > 0.0; };

// A value that passed its key's sign check but lies outside the magnitudes the engines'
// arithmetic handles (value_ranges.hpp) is refused with that range.
void refuse_outside(SectionReader& r, const std::string& key, std::optional<double> v, double lo, double hi,
                    const std::string& allowed) {
  if (v && (*v < lo || *v > hi)) r.refuse(key, allowed);
}

// Turns "section.key=value" into a TOML value in root; the value is read as TOML when it
// parses (numbers, booleans, quoted strings) and as a bare string otherwise (engine.kind=ed).
// A --set argument as it can be shown on one line: control characters as \n, \t, \xNN.
std::string printable_argument(const std::string& arg) {
  std::string out;
  for (const char c : arg) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c == '\r') out += "\\r";
    else if (u < 0x20 || u == 0x7f) out += fmt::format("\\x{:02x}", u);
    else out += c;
  }
  return out;
}

// The offset of the first byte of `text` that does not belong to a well-formed UTF-8
// sequence (RFC 3629: no overlong forms, no surrogates, at most U+10FFFF), or npos.
std::size_t first_invalid_utf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto b = static_cast<unsigned char>(text[i]);
    const std::size_t length = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xe ? 3 : (b >> 3) == 0x1e ? 4 : 0;
    if (length == 0 || i + length > text.size()) return i;
    std::uint32_t code = length == 1 ? b : b & (0x7f >> length);
    for (std::size_t k = 1; k < length; ++k) {
      const auto c = static_cast<unsigned char>(text[i + k]);
      if ((c >> 6) != 0x2) return i;
      code = (code << 6) | (c & 0x3f);
    }
    constexpr std::uint32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (code < kSmallest[length] || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return i;
    i += length;
  }
  return std::string_view::npos;
}

// The same with every byte outside ASCII escaped too: for an argument that is not UTF-8,
// whose error line must itself be text.
std::string printable_ascii(const std::string& arg) {
  std::string out;
  for (const char c : printable_argument(arg)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x80) out += fmt::format("\\x{:02x}", u);
    else out += c;
  }
  return out;
}

// A control character (a newline, a tab, NUL...) in a --set would be read as the end of
// the TOML value, the rest of the argument silently dropped or taken as another key; bytes
// that are not UTF-8 would be accepted here and written into config.toml and summary.json,
// which every TOML and JSON reader (ours included) then refuses.
void refuse_unprintable(const std::string& arg) {
  const auto bad = std::find_if(arg.begin(), arg.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 || u == 0x7f;
  });
  if (bad != arg.end())
    throw InputError(fmt::format("--set \"{}\": control character {} in the argument (one section.key=value per --set, "
                                 "printable characters only)", printable_argument(arg),
                                 printable_argument(std::string(1, *bad))));
  if (const std::size_t at = first_invalid_utf8(arg); at != std::string_view::npos)
    throw InputError(fmt::format("--set {}: byte {} (0x{:02x}) is not UTF-8 text (arguments must be UTF-8)",
                                 printable_ascii(arg), at + 1, static_cast<unsigned char>(arg[at])));
}

void apply_override(toml::table& root, const std::string& arg, std::set<std::string>& overridden) {
  refuse_unprintable(arg);
  const auto eq = arg.find('=');
  const std::string path = arg.substr(0, eq);
  const auto dot = path.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == path.size() ||
      path.find('.', dot + 1) != std::string::npos)
    throw InputError(fmt::format("--set {}: expected section.key=value (for example --set system.n=400)", arg));
  const std::string section = path.substr(0, dot), key = path.substr(dot + 1);
  const std::string text = arg.substr(eq + 1);
  toml::node* existing = root.get(section);
  if (existing == nullptr) existing = &root.insert_or_assign(section, toml::table{}).first->second;
  toml::table* table = existing->as_table();
  if (table == nullptr) throw InputError(fmt::format("--set {}: [{}] is not a table", arg, section));
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + text);
  } catch (const toml::parse_error&) {
    table->insert_or_assign(key, text);
    overridden.insert(path);
    return;
  }
  const toml::node& v = *parsed.get("v");
  if (auto i = v.value_exact<std::int64_t>()) table->insert_or_assign(key, *i);
  else if (auto d = v.value_exact<double>()) table->insert_or_assign(key, *d);
  else if (auto b = v.value_exact<bool>()) table->insert_or_assign(key, *b);
  else if (auto s = v.value_exact<std::string>()) table->insert_or_assign(key, *s);
  else if (const toml::array* a = v.as_array()) table->insert_or_assign(key, *a);
  else throw InputError(fmt::format("--set {}: the value must be a number, a boolean, a string or an array", arg));
  overridden.insert(path);
}

// [ts]: the time-stepping engine and its minimiser (docs/time_stepping.md).
TimeSteppingSettings read_ts_section(const toml::table& root, const std::string& source,
                                     const std::set<std::string>& overridden) {
  TimeSteppingSettings t;
  DahaParameters& d = t.daha;
  SectionReader ts(root, "ts", source, overridden);
  auto in_open_unit = [](double v) { return v > 0.0 && v < 1.0; };
  if (auto v = ts.choice("model", {"rigid", "almost-rigid", "non-rigid"})) t.model = static_cast<TsModel>(*v);
  d = default_daha(t.model);  // each model's own; the keys below override them
  if (auto v = ts.choice("dt_rule", {"growth", "adaptive"})) t.dt_rule = static_cast<TsDtRule>(*v);
  if (auto v = ts.choice("fall_back", {"retreat", "keep-flight"})) t.fall_back = static_cast<TsFallBack>(*v);
  const auto dt_factor = ts.real("dt_factor", [](double v) { return v > 0.0 && v <= 1.0; }, "must be a number in (0, 1]");
  refuse_outside(ts, "dt_factor", dt_factor, range::kMinDtFactor, 1.0,
                 fmt::format("must be at least {:g} (a step must move the fastest sphere by a length positions "
                             "resolve)", range::kMinDtFactor));
  if (dt_factor) t.dt_factor = *dt_factor;
  if (auto v = ts.real("dt_growth", [](double x) { return x >= 1.0 && x <= 1e3; }, "must be a number in [1, 1000]"))
    t.dt_growth = *v;
  t.delta_w = ts.real("delta_w", positive, "must be a number > 0 (a length; default 4 R)");
  if (auto v = ts.real("bond_stretch", [](double x) { return x > 0.0 && x <= 1.0; }, "must be a number in (0, 1]"))
    t.bond_stretch = *v;
  if (auto v = ts.integer("max_link_rounds", 1, 1'000'000, "must be an integer from 1 to 1000000"))
    t.max_link_rounds = static_cast<int>(*v);
  if (auto v = ts.real("retreat_overlap", [](double x) { return x > 0.0 && x <= 1.0; }, "must be a number in (0, 1]"))
    t.retreat_overlap = *v;
  if (auto v = ts.integer("retreat_pairs", 1, 1'000'000'000, "must be an integer from 1 to 1000000000"))
    t.retreat_pairs = static_cast<int>(*v);
  if (auto v = ts.real("sweep_reuse_margin", [](double x) { return x >= 0.0 && x <= 1e3; },
                       "must be a number in [0, 1000] (sphere radii)"))
    t.sweep_reuse_margin = *v;
  if (auto v = ts.real("alpha", positive, "must be a number > 0")) d.alpha = *v;
  if (auto v = ts.real("gamma", [](double x) { return x >= 0.0; }, "must be a number >= 0")) d.gamma = *v;
  if (auto v = ts.real("delta", positive, "must be a number > 0")) d.delta = *v;
  if (auto v = ts.real("c_bar", [](double x) { return x >= 0.0; }, "must be a number >= 0")) d.c_bar = *v;
  if (auto v = ts.real("c_min", [](double x) { return x >= 0.0 && x < 1.0; }, "must be a number in [0, 1)")) d.c_min = *v;
  if (auto v = ts.real("c_max", [](double x) { return x > 0.0 && x <= 1.0; }, "must be a number in (0, 1]")) d.c_max = *v;
  if (auto v = ts.real("beta_bar", positive, "must be a number > 0")) d.beta_bar = *v;
  if (auto v = ts.real("beta_max", positive, "must be a number > 0")) d.beta_max = *v;
  if (auto v = ts.real("lambda0", [](double x) { return x >= 0.0; }, "must be a number >= 0")) d.lambda0 = *v;
  if (auto v = ts.real("eps_s", in_open_unit, "must be a number in (0, 1)")) d.eps_s = *v;
  if (auto v = ts.real("eps_c", in_open_unit, "must be a number in (0, 1)")) d.eps_c = *v;
  if (auto v = ts.integer("max_iterations", 1, 100'000'000, "must be an integer from 1 to 100000000"))
    d.max_iterations = static_cast<int>(*v);
  if (auto v = ts.integer("stall_iterations", 0, 100'000'000, "must be an integer from 0 (off) to 100000000"))
    d.stall_iterations = static_cast<int>(*v);
  ts.reject_unknown_keys();
  if (d.c_min > d.c_max)
    throw InputError(fmt::format("{}: ts.c_min = {} is larger than ts.c_max = {}: the damping bounds must satisfy c_min <= c_max",
                                 source, d.c_min, d.c_max));
  return t;
}

// The [collision] keys of the rigid-body engine (docs/rigid_body.md). Returns the names of
// those given, so that other engines can refuse them.
std::vector<std::string> read_rigid_body_keys(SectionReader& col, CollisionConfig& k) {
  std::vector<std::string> given;
  auto note = [&](const char* key, bool present) { if (present) given.push_back(key); };
  const auto coagulation = col.choice("coagulation", {"aggregate", "sphere"});
  if (coagulation) k.coagulation = static_cast<Coagulation>(*coagulation);
  note("coagulation", coagulation.has_value());
  const auto radius = col.choice("merged_radius", {"constant-density", "fixed"});
  if (radius) k.merged_radius = static_cast<MergedRadius>(*radius);
  note("merged_radius", radius.has_value());
  const auto constant_speed = col.boolean("constant_speed");
  if (constant_speed) k.constant_speed = *constant_speed;
  note("constant_speed", constant_speed.has_value());
  const auto law = col.choice("restitution_law", {"constant", "bridges"});
  if (law) k.restitution_law = static_cast<RestitutionLaw>(*law);
  note("restitution_law", law.has_value());
  const auto unit = col.real("velocity_unit", positive, "must be a number > 0 (cm/s per unit of speed)");
  if (unit) k.velocity_unit = *unit;
  note("velocity_unit", unit.has_value());
  const auto mu_t = col.real("mu_t", [](double v) { return v >= 0.0 && v <= 10.0; },
                             "must be a number in [0, 10] (> 0 opposes the slip; a negative value would drive it "
                             "and create energy)");
  if (mu_t) k.mu_t = *mu_t;
  note("mu_t", mu_t.has_value());
  const auto mu_p = col.real("mu_p", [](double v) { return std::abs(v) <= 10.0; }, "must be a number in [-10, 10]");
  if (mu_p) k.mu_p = *mu_p;
  note("mu_p", mu_p.has_value());
  k.energy_threshold = col.real("energy_threshold", positive, "must be a number > 0 (an energy)");
  note("energy_threshold", k.energy_threshold.has_value());
  k.fragmentation_energy = col.real("fragmentation_energy", positive, "must be a number > 0 (an energy)");
  note("fragmentation_energy", k.fragmentation_energy.has_value());
  return given;
}

// Rules between the rigid-body keys and the rest.
void check_rigid_body_rules(const Config& c, const std::vector<std::string>& given, bool restitution_given) {
  const std::string& source = c.source;
  const CollisionConfig& k = c.collision;
  auto has = [&](const char* key) { return std::find(given.begin(), given.end(), key) != given.end(); };
  if (c.engine.kind != EngineKind::rigid_body) {
    if (!given.empty())
      throw InputError(fmt::format("{}: collision.{} is a key of the rigid-body engine: it needs engine.kind = "
                                   "\"rigid-body\"", source, given.front()));
    if (k.outcome == CollisionOutcome::energy_threshold)
      throw InputError(fmt::format("{}: collision.outcome = \"energy-threshold\" needs engine.kind = \"rigid-body\"",
                                   source));
    if (c.stop.aggregated_fraction)
      throw InputError(fmt::format("{}: stop.aggregated_fraction needs engine.kind = \"rigid-body\"", source));
    return;
  }
  if (has("energy_threshold") && k.outcome != CollisionOutcome::energy_threshold)
    throw InputError(fmt::format("{}: collision.energy_threshold is only used with collision.outcome = "
                                 "\"energy-threshold\"", source));
  if (k.coagulation != Coagulation::sphere) {
    for (const char* key : {"merged_radius", "constant_speed"})
      if (has(key))
        throw InputError(fmt::format("{}: collision.{} is only used with collision.coagulation = \"sphere\"", source, key));
  } else if (k.fragmentation_energy) {
    throw InputError(fmt::format("{}: collision.fragmentation_energy breaks aggregates up: it needs "
                                 "collision.coagulation = \"aggregate\"", source));
  }
  if (k.constant_speed && c.initial.velocities != InitialVelocities::fixed_speed)
    throw InputError(fmt::format("{}: collision.constant_speed keeps every speed at initial.speed: it needs "
                                 "initial.velocities = \"fixed-speed\"", source));
  if (k.restitution_law == RestitutionLaw::bridges && restitution_given)
    throw InputError(fmt::format("{}: give collision.restitution (a constant) or collision.restitution_law = "
                                 "\"bridges\", not both", source));
  if (has("velocity_unit") && k.restitution_law != RestitutionLaw::bridges)
    throw InputError(fmt::format("{}: collision.velocity_unit is only used with collision.restitution_law = "
                                 "\"bridges\"", source));
  if (c.system.dimension == 2 && k.mu_p != 0.0)
    throw InputError(fmt::format("{}: collision.mu_p = {}: in 2D the contact has one tangent (use mu_t)", source, k.mu_p));
}

// x rounded up to three significant digits: a bound to quote that is itself allowed.
double rounded_up(double x) {
  const double unit = std::pow(10.0, std::floor(std::log10(x)) - 2.0);
  return std::ceil(x / unit) * unit;
}

// The box and the skin against the radius (value_ranges.hpp). A state file gives its own
// radii: initial/state_ranges.cpp checks those runs against them.
void check_length_ratios(const Config& c, SectionReader& sys, SectionReader& eng) {
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

Config read_config(const toml::table& root, const std::string& source, const std::set<std::string>& overridden) {
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
  Config c;
  c.source = source;

  SectionReader sys(root, "system", source, overridden);
  if (auto v = sys.integer("dimension", 2, 3, "must be 2 or 3")) c.system.dimension = static_cast<int>(*v);
  if (auto v = sys.integer("n", 1, 100'000'000, "must be an integer from 1 to 100000000")) c.system.n = *v;
  c.system.volume_fraction = sys.real("volume_fraction", [](double v) { return v > 0.0 && v < 1.0; },
                                      "must be a number in (0, 1)");
  c.system.box_length = sys.real("box_length", positive, "must be a number > 0");
  refuse_outside(sys, "box_length", c.system.box_length, 0.0, range::kMaxBoxLength,
                 fmt::format("must be at most {:g} ({:g} times the largest radius allowed)", range::kMaxBoxLength,
                             range::kMaxBoxToRadius));
  const auto radius = sys.real("radius", positive, "must be a number > 0");
  refuse_outside(sys, "radius", radius, range::kMinRadius, range::kMaxRadius,
                 fmt::format("must be from {:g} to {:g} (choose units in which radii are near 1)", range::kMinRadius,
                             range::kMaxRadius));
  if (radius) c.system.radius = *radius;
  const auto mass = sys.real("mass", positive, "must be a number > 0");
  refuse_outside(sys, "mass", mass, range::kMinMass, range::kMaxMass,
                 fmt::format("must be from {:g} to {:g} (choose units in which masses are near 1)", range::kMinMass,
                             range::kMaxMass));
  if (mass) c.system.mass = *mass;
  if (auto v = sys.choice("boundary", {"walls", "periodic"})) c.system.boundary = static_cast<Boundary>(*v);
  sys.reject_unknown_keys();

  SectionReader ini(root, "initial", source, overridden);
  if (auto v = ini.choice("positions", {"lattice", "random", "file"})) c.initial.positions = static_cast<InitialPositions>(*v);
  if (auto v = ini.choice("velocities", {"fixed-speed", "uniform", "gaussian"}))
    c.initial.velocities = static_cast<InitialVelocities>(*v);
  const auto speed = ini.real("speed", [](double v) { return v >= 0.0; }, "must be a number >= 0");
  refuse_outside(ini, "speed", speed, 0.0, range::kMaxSpeed,
                 fmt::format("must be at most {:g} (choose units in which speeds are near 1)", range::kMaxSpeed));
  if (speed) c.initial.speed = *speed;
  if (auto v = ini.string("file", "must be a file name (a string)")) c.initial.file = *v;
  if (auto v = ini.boolean("zero_momentum")) c.initial.zero_momentum = *v;
  if (auto v = ini.integer("seed", 0, std::numeric_limits<std::int64_t>::max(), "must be an integer >= 0"))
    c.initial.seed = static_cast<std::uint64_t>(*v);
  ini.reject_unknown_keys();

  SectionReader col(root, "collision", source, overridden);
  if (auto v = col.choice("outcome", {"stick", "bounce", "energy-threshold"}))
    c.collision.outcome = static_cast<CollisionOutcome>(*v);
  const auto restitution = col.real("restitution", [](double v) { return v >= 0.0 && v <= 1.0; }, "must be a number in [0, 1]");
  if (restitution) c.collision.restitution = *restitution;
  c.collision.tc_time = col.real("tc_time", [](double v) { return v >= 0.0; }, "must be a number >= 0");
  const std::vector<std::string> rigid_keys = read_rigid_body_keys(col, c.collision);
  col.reject_unknown_keys();

  SectionReader eng(root, "engine", source, overridden);
  if (auto v = eng.choice("kind", {"ed", "ed-naive", "ts", "rigid-body"})) c.engine.kind = static_cast<EngineKind>(*v);
  c.engine.skin = eng.real("skin", positive, "must be a number > 0 (a length)");
  eng.reject_unknown_keys();

  c.ts = read_ts_section(root, source, overridden);

  SectionReader stop(root, "stop", source, overridden);
  // The reader refuses values of another type; the range is check_stop_*'s, which
  // Python's Simulation.run applies too.
  const auto any_number = [](double) { return true; };
  if (auto v = stop.integer("clusters", std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max(),
                            std::string(kStopClustersAllowed))) {
    check_stop_clusters(*v, stop.name_of("clusters"));
    c.stop.clusters = *v;
  }
  if (auto v = stop.real("time", any_number, std::string(kStopDurationAllowed), true)) {
    check_stop_duration(*v, stop.name_of("time"));
    c.stop.time = *v;
  }
  if (auto v = stop.real("wall_seconds", any_number, std::string(kStopDurationAllowed), true)) {
    check_stop_duration(*v, stop.name_of("wall_seconds"));
    c.stop.wall_seconds = *v;
  }
  c.stop.aggregated_fraction = stop.real("aggregated_fraction", [](double v) { return v > 0.0 && v <= 1.0; },
                                         "must be a number in (0, 1]");
  stop.reject_unknown_keys();

  SectionReader out(root, "output", source, overridden);
  if (auto v = out.real("timeseries_interval", [](double x) { return x >= 0.0; }, "must be a number >= 0 (0: none)"))
    c.output.timeseries_interval = *v;
  if (auto v = out.boolean("xyz")) c.output.xyz = *v;
  if (auto v = out.real("snapshot_every", [](double x) { return x >= 0.0; }, "must be a number >= 0 (0: no trajectory)"))
    c.output.snapshot_every = *v;
  if (auto v = out.choices("snapshot_formats", {"h5md", "xyz", "gsd"})) {
    c.output.snapshot_formats.clear();
    for (int k : *v) c.output.snapshot_formats.push_back(static_cast<SnapshotFormat>(k));
  }
  if (auto v = out.choice("snapshot_precision", {"single", "double"}))
    c.output.snapshot_precision = static_cast<SnapshotPrecision>(*v);
  if (auto v = out.boolean("h5md_pad_3d")) c.output.h5md_pad_3d = *v;
  if (auto v = out.real("checkpoint_every", [](double x) { return x >= 0.0; },
                        "must be a number of wall seconds >= 0 (0: checkpoints on SIGINT/SIGTERM only)"))
    c.output.checkpoint_every = *v;
  out.reject_unknown_keys();

  // Rules that involve several keys.
  check_rigid_body_rules(c, rigid_keys, restitution.has_value());
  if (c.output.snapshot_every > 0.0 && c.output.snapshot_formats.empty())
    throw InputError(fmt::format("{}: output.snapshot_every = {} but output.snapshot_formats is empty "
                                 "(give \"h5md\", \"xyz\" and/or \"gsd\", or set snapshot_every = 0)", source, c.output.snapshot_every));
  const bool from_file = c.initial.positions == InitialPositions::file;
  if (c.engine.kind == EngineKind::ts && c.collision.outcome != CollisionOutcome::stick)
    throw InputError(fmt::format("{}: engine.kind = \"ts\" simulates sticking only: collision.outcome must be \"stick\" "
                                 "(use engine.kind = \"ed\" for bounces)", source));
  if (c.system.volume_fraction && c.system.box_length)
    throw InputError(fmt::format("{}: give system.volume_fraction or system.box_length, not both", source));
  if (from_file && c.initial.file.empty())
    throw InputError(fmt::format("{}: initial.positions = \"file\" needs initial.file", source));
  if (from_file && !c.system.box_length)
    throw InputError(fmt::format("{}: initial.positions = \"file\" needs system.box_length (the file gives no box)", source));
  if (!from_file && !c.initial.file.empty())
    throw InputError(fmt::format("{}: initial.file is only read when initial.positions = \"file\"", source));
  if (!from_file && !c.system.box_length && !c.system.volume_fraction)
    c.system.volume_fraction = kDefaultVolumeFraction;
  if (c.system.volume_fraction) {
    // Densest packings: hexagonal discs pi / (2 sqrt 3), spheres pi / (3 sqrt 2).
    const double densest = c.system.dimension == 2 ? std::numbers::pi / (2 * std::sqrt(3.0))
                                                   : std::numbers::pi / (3 * std::sqrt(2.0));
    if (*c.system.volume_fraction >= densest)
      throw InputError(fmt::format("{}: system.volume_fraction = {}: no packing of equal {} is that dense (the densest is {:.4f})",
                                   source, *c.system.volume_fraction, c.system.dimension == 2 ? "discs" : "spheres", densest));
  }
  if (!from_file) check_length_ratios(c, sys, eng);
  return c;
}

Config parse_root(toml::table root, const std::string& source, const std::vector<std::string>& overrides) {
  std::set<std::string> overridden;
  for (const std::string& o : overrides) apply_override(root, o, overridden);
  return read_config(root, source, overridden);
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

Config parse_config_text(std::string_view text, const std::string& source_name, const std::vector<std::string>& overrides) {
  refuse_deeply_dotted_toml(text, source_name);
  toml::table root;
  try {
    root = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    throw InputError(parse_error_message(e, source_name));
  }
  return parse_root(std::move(root), source_name, overrides);
}

Config load_config(const std::string& path, const std::vector<std::string>& overrides) {
  if (path.empty()) return parse_config_text("", "(defaults)", overrides);
  Config c = parse_config_text(read_text_file(path, "config file", kMaxSettingsFileBytes), path, overrides);
  // A relative initial.file written in a config file is relative to that file; one given
  // with --set is relative to the working directory.
  const bool from_set = std::any_of(overrides.begin(), overrides.end(),
                                    [](const std::string& o) { return o.rfind("initial.file=", 0) == 0; });
  const std::filesystem::path file(c.initial.file);
  if (!c.initial.file.empty() && !from_set && file.is_relative())
    c.initial.file = (std::filesystem::path(path).parent_path() / file).lexically_normal().string();
  return c;
}

void check_stop_clusters(std::int64_t clusters, std::string_view name) {
  if (clusters < 1) throw InputError(fmt::format("{} = {}: {}", name, clusters, kStopClustersAllowed));
}

void check_stop_duration(double value, std::string_view name) {
  if (!(value > 0.0)) throw InputError(fmt::format("{} = {}: {}", name, value, kStopDurationAllowed));
}

double resolved_box_length(const Config& c) {
  if (c.system.box_length) return *c.system.box_length;
  const double n = static_cast<double>(c.system.n), r = c.system.radius;
  const double vf = c.system.volume_fraction.value_or(kDefaultVolumeFraction);
  if (c.system.dimension == 2) return std::sqrt(n * std::numbers::pi * r * r / vf);
  return std::cbrt(n * 4.0 / 3.0 * std::numbers::pi * r * r * r / vf);
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
std::string_view to_string(CollisionOutcome o) {
  static constexpr std::string_view names[] = {"stick", "bounce", "energy-threshold"};
  return names[static_cast<int>(o)];
}
std::string_view to_string(Coagulation c) { return c == Coagulation::aggregate ? "aggregate" : "sphere"; }
std::string_view to_string(MergedRadius r) { return r == MergedRadius::constant_density ? "constant-density" : "fixed"; }
std::string_view to_string(RestitutionLaw l) { return l == RestitutionLaw::constant ? "constant" : "bridges"; }

namespace {

// The resolved configuration as ordered sections of (key, value), the single source of
// both the TOML and the JSON rendering.
using Value = std::variant<std::int64_t, double, bool, std::string, std::vector<std::string>>;
using Section = std::pair<std::string, std::vector<std::pair<std::string, Value>>>;

std::vector<Section> entries(const Config& c) {
  auto str = [](std::string_view v) { return Value(std::string(v)); };
  Section system{"system", {{"dimension", std::int64_t{c.system.dimension}}, {"n", c.system.n}}};
  if (c.system.volume_fraction) system.second.push_back({"volume_fraction", *c.system.volume_fraction});
  if (c.system.box_length) system.second.push_back({"box_length", *c.system.box_length});
  system.second.push_back({"radius", c.system.radius});
  system.second.push_back({"mass", c.system.mass});
  system.second.push_back({"boundary", str(to_string(c.system.boundary))});
  Section initial{"initial",
                  {{"positions", str(to_string(c.initial.positions))},
                   {"velocities", str(to_string(c.initial.velocities))},
                   {"speed", c.initial.speed}}};
  if (!c.initial.file.empty()) initial.second.push_back({"file", c.initial.file});
  initial.second.push_back({"zero_momentum", c.initial.zero_momentum});
  initial.second.push_back({"seed", static_cast<std::int64_t>(c.initial.seed)});
  Section collision{"collision", {{"outcome", str(to_string(c.collision.outcome))}, {"restitution", c.collision.restitution}}};
  if (c.collision.tc_time) collision.second.push_back({"tc_time", *c.collision.tc_time});
  const bool rigid = c.engine.kind == EngineKind::rigid_body;
  if (rigid) {
    const CollisionConfig& k = c.collision;
    auto& keys = collision.second;
    keys.push_back({"coagulation", str(to_string(k.coagulation))});
    if (k.coagulation == Coagulation::sphere) {
      keys.push_back({"merged_radius", str(to_string(k.merged_radius))});
      keys.push_back({"constant_speed", k.constant_speed});
    }
    keys.push_back({"restitution_law", str(to_string(k.restitution_law))});
    if (k.restitution_law == RestitutionLaw::bridges) {
      std::erase_if(keys, [](const auto& kv) { return kv.first == "restitution"; });
      keys.push_back({"velocity_unit", k.velocity_unit});
    }
    keys.push_back({"mu_t", k.mu_t});
    if (c.system.dimension == 3) keys.push_back({"mu_p", k.mu_p});
    if (k.energy_threshold) keys.push_back({"energy_threshold", *k.energy_threshold});
    if (k.fragmentation_energy) keys.push_back({"fragmentation_energy", *k.fragmentation_energy});
  }
  Section engine{"engine", {{"kind", str(to_string(c.engine.kind))}}};
  if (c.engine.skin) engine.second.push_back({"skin", *c.engine.skin});
  const TimeSteppingSettings& t = c.ts;
  Section ts{"ts",
             {{"model", str(to_string(t.model))},
              {"dt_rule", str(to_string(t.dt_rule))},
              {"fall_back", str(to_string(t.fall_back))},
              {"dt_factor", t.dt_factor},
              {"dt_growth", t.dt_growth}}};
  if (t.delta_w) ts.second.push_back({"delta_w", *t.delta_w});
  ts.second.push_back({"bond_stretch", t.bond_stretch});
  const DahaParameters& d = t.daha;
  for (auto&& [key, value] : std::initializer_list<std::pair<const char*, double>>{
           {"alpha", d.alpha}, {"gamma", d.gamma}, {"delta", d.delta}, {"c_bar", d.c_bar}, {"c_min", d.c_min}, {"c_max", d.c_max},
           {"beta_bar", d.beta_bar}, {"beta_max", d.beta_max}, {"lambda0", d.lambda0}, {"eps_s", d.eps_s},
           {"eps_c", d.eps_c}})
    ts.second.push_back({key, value});
  ts.second.push_back({"max_iterations", std::int64_t{d.max_iterations}});
  ts.second.push_back({"stall_iterations", std::int64_t{d.stall_iterations}});
  ts.second.push_back({"max_link_rounds", std::int64_t{t.max_link_rounds}});
  ts.second.push_back({"retreat_overlap", t.retreat_overlap});
  ts.second.push_back({"retreat_pairs", std::int64_t{t.retreat_pairs}});
  ts.second.push_back({"sweep_reuse_margin", t.sweep_reuse_margin});
  Section stop{"stop", {{"clusters", c.stop.clusters}, {"time", c.stop.time}, {"wall_seconds", c.stop.wall_seconds}}};
  if (c.stop.aggregated_fraction) stop.second.push_back({"aggregated_fraction", *c.stop.aggregated_fraction});
  std::vector<std::string> formats;
  for (SnapshotFormat f : c.output.snapshot_formats) formats.emplace_back(to_string(f));
  Section output{"output",
                 {{"timeseries_interval", c.output.timeseries_interval},
                  {"xyz", c.output.xyz},
                  {"snapshot_every", c.output.snapshot_every},
                  {"snapshot_formats", formats},
                  {"snapshot_precision", str(to_string(c.output.snapshot_precision))},
                  {"checkpoint_every", c.output.checkpoint_every}}};
  // Written when set only: the configuration files of runs without it stay as they were.
  if (c.output.h5md_pad_3d) output.second.push_back({"h5md_pad_3d", true});
  if (c.engine.kind != EngineKind::ts) return {system, initial, collision, engine, stop, output};
  return {system, initial, collision, engine, ts, stop, output};
}

std::string toml_value(const Value& v) {
  if (auto i = std::get_if<std::int64_t>(&v)) return fmt::format("{}", *i);
  if (auto b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  if (auto d = std::get_if<double>(&v)) {
    if (std::isinf(*d)) return *d > 0 ? "inf" : "-inf";
    std::string text = fmt::format("{}", *d);  // shortest form that reads back exactly
    if (text.find_first_of(".e") == std::string::npos) text += ".0";
    return text;
  }
  if (auto list = std::get_if<std::vector<std::string>>(&v)) {
    std::string text = "[";
    for (const std::string& item : *list) text += (text.size() > 1 ? ", " : "") + toml_value(item);
    return text + "]";
  }
  std::string quoted = "\"";
  for (char ch : std::get<std::string>(v)) {
    if (ch == '"' || ch == '\\') quoted += '\\';
    if (static_cast<unsigned char>(ch) < 0x20) quoted += fmt::format("\\u{:04x}", static_cast<int>(ch));
    else quoted += ch;
  }
  return quoted + "\"";
}

}  // namespace

std::string to_toml_text(const Config& c) {
  std::string out;
  for (const auto& [section, keys] : entries(c)) {
    out += fmt::format("{}[{}]\n", out.empty() ? "" : "\n", section);
    for (const auto& [key, value] : keys) out += fmt::format("{} = {}\n", key, toml_value(value));
  }
  return out;
}

std::string to_json_text(const Config& c) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [section, keys] : entries(c)) {
    nlohmann::ordered_json& js = j[section];
    js = nlohmann::ordered_json::object();
    for (const auto& entry : keys) {
      const auto& key = entry.first;  // not a structured binding: clang 14 cannot capture one in a lambda
      std::visit([&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>) {
          if (std::isinf(v)) { js[key] = nullptr; return; }  // JSON has no infinity
        }
        js[key] = v;
      }, entry.second);
    }
  }
  return j.dump(2);
}

}  // namespace ballagg
