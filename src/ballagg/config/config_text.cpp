// The resolved configuration as text: TOML (config.toml) and JSON (summary.json).
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "ballagg/config/config.hpp"

namespace ballagg {

namespace {

// The resolved configuration as ordered sections of (key, value), the single source of
// both the TOML and the JSON rendering.
using Value = std::variant<std::int64_t, double, bool, std::string, std::vector<std::string>, std::vector<double>>;
using Section = std::pair<std::string, std::vector<std::pair<std::string, Value>>>;

// The radius law and the parameters it reads, written for polydisperse runs only (the
// configuration files of runs with one radius stay as they were).
void add_radius_distribution(const SystemConfig& s, std::vector<std::pair<std::string, Value>>& keys) {
  const RadiusDistribution& d = s.radius_distribution;
  if (!polydisperse(s)) return;
  keys.push_back({"radius_distribution", std::string(to_string(d.law))});
  if (d.law == RadiusLaw::lognormal || d.law == RadiusLaw::normal) keys.push_back({"radius_sigma", d.sigma});
  if (d.min > 0.0) keys.push_back({"radius_min", d.min});
  if (!std::isinf(d.max)) keys.push_back({"radius_max", d.max});
  if (d.law == RadiusLaw::power_law) keys.push_back({"radius_exponent", d.exponent});
  if (d.law == RadiusLaw::discrete) {
    keys.push_back({"radii", d.radii});
    if (!d.weights.empty()) keys.push_back({"radius_weights", d.weights});
  }
}

Value str(std::string_view v) { return Value(std::string(v)); }

Section system_section(const Config& c) {
  Section system{"system", {{"dimension", std::int64_t{c.system.dimension}}, {"n", c.system.n}}};
  if (c.system.volume_fraction) system.second.push_back({"volume_fraction", *c.system.volume_fraction});
  if (c.system.box_length) system.second.push_back({"box_length", *c.system.box_length});
  system.second.push_back({"radius", c.system.radius});
  add_radius_distribution(c.system, system.second);
  if (c.system.density) system.second.push_back({"density", *c.system.density});
  else system.second.push_back({"mass", c.system.mass});
  system.second.push_back({"boundary", str(to_string(c.system.boundary))});
  return system;
}

Section initial_section(const Config& c) {
  Section initial{"initial",
                  {{"positions", str(to_string(c.initial.positions))},
                   {"velocities", str(to_string(c.initial.velocities))},
                   {"speed", c.initial.speed}}};
  // Written when set only: the configuration files of runs without it stay as they were.
  if (c.initial.lattice_spacing) initial.second.push_back({"lattice_spacing", *c.initial.lattice_spacing});
  if (!c.initial.file.empty()) initial.second.push_back({"file", c.initial.file});
  // Written when the clock does not start at 0 only: other runs' files stay as they were.
  if (c.initial.time != 0.0) initial.second.push_back({"time", c.initial.time});
  initial.second.push_back({"zero_momentum", c.initial.zero_momentum});
  initial.second.push_back({"seed", static_cast<std::int64_t>(c.initial.seed)});
  return initial;
}

// The rigid-body engine's collision law (RigidBodyLaw), after the keys every engine reads.
void add_rigid_body_law(const RigidBodyLaw& k, int dimension, std::vector<std::pair<std::string, Value>>& keys) {
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
  if (dimension == 3) keys.push_back({"mu_p", k.mu_p});
  if (k.energy_threshold) keys.push_back({"energy_threshold", *k.energy_threshold});
  if (k.energy_threshold_factor) keys.push_back({"energy_threshold_factor", *k.energy_threshold_factor});
  // Written when on only: the configuration files of runs without it stay as they were.
  if (k.fragmentation != Fragmentation::off) keys.push_back({"fragmentation", str(to_string(k.fragmentation))});
  if (k.fragmentation_factor) keys.push_back({"fragmentation_factor", *k.fragmentation_factor});
  if (k.fragmentation_energy) keys.push_back({"fragmentation_energy", *k.fragmentation_energy});
}

Section collision_section(const Config& c) {
  Section collision{"collision", {{"outcome", str(to_string(c.collision.outcome))}, {"restitution", c.collision.restitution}}};
  if (c.collision.tc_time) collision.second.push_back({"tc_time", *c.collision.tc_time});
  if (c.engine.kind == EngineKind::rigid_body) add_rigid_body_law(c.rigid_body, c.system.dimension, collision.second);
  return collision;
}

Section ts_section(const TimeSteppingSettings& t) {
  Section ts{"ts",
             {{"model", str(to_string(t.model))},
              {"dt_rule", str(to_string(t.dt_rule))},
              {"fall_back", str(to_string(t.fall_back))},
              {"dt_factor", t.dt_factor},
              {"dt_growth", t.dt_growth}}};
  // The method and the keys of our additions: written for the method that has them, so
  // the file reads back (and the configuration files of ts.method = "ours" stay as they were).
  const bool paper = t.method == TsMethod::paper;
  if (paper) {
    ts.second.insert(ts.second.begin(), std::pair<std::string, Value>{"method", str(to_string(t.method))});
    std::erase_if(ts.second, [](const auto& kv) { return kv.first == "fall_back"; });
  }
  if (t.delta_w) ts.second.push_back({"delta_w", *t.delta_w});
  if (!paper) ts.second.push_back({"bond_stretch", t.bond_stretch});
  const DahaParameters& d = t.daha;
  for (auto&& [key, value] : std::initializer_list<std::pair<const char*, double>>{
           {"alpha", d.alpha}, {"gamma", d.gamma}, {"delta", d.delta}, {"c_bar", d.c_bar}, {"c_min", d.c_min}, {"c_max", d.c_max},
           {"beta_bar", d.beta_bar}, {"beta_max", d.beta_max}, {"lambda0", d.lambda0}, {"eps_s", d.eps_s},
           {"eps_c", d.eps_c}})
    ts.second.push_back({key, value});
  ts.second.push_back({"max_iterations", std::int64_t{d.max_iterations}});
  ts.second.push_back({"stall_iterations", std::int64_t{d.stall_iterations}});
  ts.second.push_back({"max_link_rounds", std::int64_t{t.max_link_rounds}});
  if (!paper) {
    ts.second.push_back({"retreat_overlap", t.retreat_overlap});
    ts.second.push_back({"retreat_pairs", std::int64_t{t.retreat_pairs}});
    ts.second.push_back({"sweep_reuse_margin", t.sweep_reuse_margin});
  }
  return ts;
}

Section output_section(const Config& c) {
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
  return output;
}

std::vector<Section> entries(const Config& c) {
  Section engine{"engine", {{"kind", str(to_string(c.engine.kind))}}};
  if (c.engine.skin) engine.second.push_back({"skin", *c.engine.skin});
  Section stop{"stop", {{"clusters", c.stop.clusters}, {"time", c.stop.time}, {"wall_seconds", c.stop.wall_seconds}}};
  if (c.stop.aggregated_fraction) stop.second.push_back({"aggregated_fraction", *c.stop.aggregated_fraction});
  std::vector<Section> sections{system_section(c), initial_section(c), collision_section(c), engine};
  if (c.engine.kind == EngineKind::ts) sections.push_back(ts_section(c.ts));
  sections.push_back(stop);
  sections.push_back(output_section(c));
  return sections;
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
  if (auto numbers = std::get_if<std::vector<double>>(&v)) {
    std::string text = "[";
    for (double x : *numbers) text += (text.size() > 1 ? ", " : "") + toml_value(x);
    return text + "]";
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
