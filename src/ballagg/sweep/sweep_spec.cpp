#include "ballagg/sweep/sweep_spec.hpp"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <set>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "ballagg/config/text_file.hpp"

namespace ballagg {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxRealizations = 1'000'000;

int line_of(const toml::node& n) { return static_cast<int>(n.source().begin.line); }

class SpecReader {
 public:
  explicit SpecReader(const std::string& source) : source_(source) {}

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw InputError(line > 0 ? fmt::format("{}:{}: {}", source_, line, what) : fmt::format("{}: {}", source_, what));
  }

  // A configuration value as --set text, in TOML syntax.
  std::string value_text(const toml::node& v, const std::string& key) const {
    if (auto i = v.value_exact<std::int64_t>()) return fmt::format("{}", *i);
    if (auto d = v.value_exact<double>()) return fmt::format("{}", *d);
    if (auto b = v.value_exact<bool>()) return *b ? "true" : "false";
    if (auto s = v.value_exact<std::string>()) {
      std::string text = *s;
      if (key == "initial.file" && !text.empty() && fs::path(text).is_relative())
        text = (fs::path(source_).parent_path() / text).lexically_normal().string();
      std::string quoted = "\"";
      for (char c : text) {
        if (c == '"' || c == '\\') quoted += '\\';
        quoted += c;
      }
      return quoted + "\"";
    }
    fail(line_of(v), fmt::format("{}: a value must be a number, a boolean or a string", key));
  }

  // The dotted keys of a table and their nodes: {"system.n": node} for `system.n = ...`
  // or `[grid.system] n = ...`.
  void leaves(const toml::table& t, const std::string& prefix, std::vector<std::pair<std::string, const toml::node*>>& out) const {
    for (auto&& [k, node] : t) {
      const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
      if (const toml::table* sub = node.as_table()) leaves(*sub, key, out);
      else out.emplace_back(key, &node);
    }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return line_of(*a.second) < line_of(*b.second); });
  }

  void check_key(const std::string& key, int line, const std::string& where) const {
    const auto dot = key.find('.');
    if (dot == std::string::npos || key.find('.', dot + 1) != std::string::npos)
      fail(line, fmt::format("{} '{}' must be a configuration key section.key (for example system.n)", where, key));
    if (key == "initial.seed" && where == "variant key")
      fail(line, "initial.seed cannot be set in a variant: vary it in [grid] or set [sweep] seed_base");
  }

 private:
  const std::string& source_;
};

SweepAxis read_axis(const SpecReader& r, const std::string& key, const toml::node& node, const toml::array& values) {
  if (values.empty())
    r.fail(line_of(node), fmt::format("grid {} must be a non-empty array of values, e.g. {} = [1, 2]", key, key));
  SweepAxis axis{key, {}};
  std::set<std::string> seen;
  for (const toml::node& v : values) {
    const int line = line_of(v) > 0 ? line_of(v) : line_of(node);
    SweepSetting s{key, r.value_text(v, key), line};
    if (!seen.insert(s.value).second) r.fail(line, fmt::format("grid {}: the value {} appears twice", key, s.value));
    axis.values.push_back(std::move(s));
  }
  return axis;
}

// The root's sections: [sweep], [grid] and [[variants]] only.
void check_sections(const SpecReader& r, const toml::table& root) {
  for (auto&& [k, node] : root) {
    const std::string name(k.str());
    if (name != "sweep" && name != "grid" && name != "variants")
      r.fail(line_of(node), fmt::format("unknown section [{}] (a sweep file has [sweep], [grid] and [[variants]])", name));
  }
}

// [sweep]: base, realizations, seed_base.
void read_sweep_section(const SpecReader& r, const toml::node& node, SweepSpec& spec) {
  const toml::table* t = node.as_table();
  if (t == nullptr) r.fail(line_of(node), "sweep must be a section ([sweep])");
  for (auto&& [k, v] : *t) {
    const std::string key(k.str());
    if (key == "base") {
      auto s = v.value_exact<std::string>();
      if (!s || s->empty()) r.fail(line_of(v), "sweep.base must be the path of a configuration file (a string)");
      const fs::path p(*s);
      spec.base = p.is_relative() ? (fs::path(spec.source).parent_path() / p).lexically_normal().string() : *s;
    } else if (key == "realizations") {
      auto i = v.value_exact<std::int64_t>();
      if (!i || *i < 1 || *i > kMaxRealizations)
        r.fail(line_of(v), fmt::format("sweep.realizations must be an integer from 1 to {}", kMaxRealizations));
      spec.realizations = static_cast<int>(*i);
    } else if (key == "seed_base") {
      auto i = v.value_exact<std::int64_t>();
      if (!i || *i < 0) r.fail(line_of(v), "sweep.seed_base must be an integer >= 0");
      spec.seed_base = static_cast<std::uint64_t>(*i);
    } else {
      r.fail(line_of(v), fmt::format("unknown key 'sweep.{}' (keys of [sweep]: base, realizations, seed_base)", key));
    }
  }
}

// One [[variants]] table: its label, its settings and its own values of grid keys.
SweepVariant read_variant(const SpecReader& r, const toml::node& item) {
  const toml::table* t = item.as_table();
  if (t == nullptr) r.fail(line_of(item), "each of variants must be a table ([[variants]])");
  SweepVariant v;
  v.line = line_of(item);
  std::vector<std::pair<std::string, const toml::node*>> keys;
  r.leaves(*t, "", keys);
  for (const auto& [key, value] : keys) {
    if (key == "label") {
      auto s = value->value_exact<std::string>();
      if (!s || s->empty()) r.fail(line_of(*value), "variants label must be a non-empty string");
      v.label = *s;
      continue;
    }
    r.check_key(key, line_of(*value), "variant key");
    if (const toml::array* values = value->as_array()) {
      v.own_values.push_back(read_axis(r, key, *value, *values));
      continue;
    }
    v.settings.push_back({key, r.value_text(*value, key), line_of(*value)});
  }
  if (v.label.empty()) {
    for (const SweepSetting& s : v.settings) v.label += (v.label.empty() ? "" : ",") + s.key + "=" + s.value;
  }
  return v;
}

void read_variants(const SpecReader& r, const toml::node& node, SweepSpec& spec) {
  const toml::array* a = node.as_array();
  if (a == nullptr || a->empty()) r.fail(line_of(node), "variants must be an array of tables ([[variants]] sections)");
  for (const toml::node& item : *a) spec.variants.push_back(read_variant(r, item));
}

// [grid]: an array of values per key, a key set by no variant.
void read_grid(const SpecReader& r, const toml::node& node, SweepSpec& spec) {
  const toml::table* t = node.as_table();
  if (t == nullptr) r.fail(line_of(node), "grid must be a section ([grid])");
  std::vector<std::pair<std::string, const toml::node*>> keys;
  r.leaves(*t, "", keys);
  for (const auto& [key, value] : keys) {
    r.check_key(key, line_of(*value), "grid key");
    const toml::array* values = value->as_array();
    if (values == nullptr)
      r.fail(line_of(*value), fmt::format("grid {} must be a non-empty array of values, e.g. {} = [1, 2]", key, key));
    for (const SweepVariant& variant : spec.variants)
      for (const SweepSetting& s : variant.settings)
        if (s.key == key)
          r.fail(line_of(*value), fmt::format("grid {}: also set by the variant at line {} (set it in one place)", key, variant.line));
    spec.axes.push_back(read_axis(r, key, *value, *values));
  }
}

// A variant's own array replaces the values of a grid key: the key must be in [grid].
void check_variant_values(const SpecReader& r, const SweepSpec& spec) {
  for (const SweepVariant& variant : spec.variants)
    for (const SweepAxis& own : variant.own_values)
      if (std::none_of(spec.axes.begin(), spec.axes.end(), [&](const SweepAxis& a) { return a.key == own.key; }))
        r.fail(own.values.front().line, fmt::format("variant values for {}: not a key of [grid] (a variant's array "
                                                    "replaces the grid's values for that key)", own.key));
}

}  // namespace

SweepSpec parse_sweep_text(const std::string& text, const std::string& source) {
  SpecReader r(source);
  SweepSpec spec;
  spec.source = source;
  spec.text = text;
  toml::table root;
  try {
    refuse_deeply_dotted_toml(text, source);
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    r.fail(static_cast<int>(e.source().begin.line), fmt::format("invalid TOML: {}", e.description()));
  }
  check_sections(r, root);
  if (const toml::node* node = root.get("sweep")) read_sweep_section(r, *node, spec);
  if (const toml::node* node = root.get("variants")) read_variants(r, *node, spec);
  if (spec.variants.empty()) spec.variants.push_back({});  // the one empty variant, line 0
  if (const toml::node* node = root.get("grid")) read_grid(r, *node, spec);
  check_variant_values(r, spec);
  return spec;
}

bool has_variants(const SweepSpec& spec) { return spec.variants.size() > 1 || spec.variants.front().line > 0; }

SweepSpec load_sweep(const std::string& path) { return parse_sweep_text(read_text_file(path, "sweep file", kMaxSettingsFileBytes), path); }

std::vector<SweepPoint> sweep_points(const SweepSpec& spec) {
  std::vector<SweepPoint> points;
  for (const SweepVariant& v : spec.variants) {
    std::vector<const SweepAxis*> axes;
    std::size_t per_variant = 1;
    for (const SweepAxis& a : spec.axes) {
      const auto own = std::find_if(v.own_values.begin(), v.own_values.end(), [&](const SweepAxis& o) { return o.key == a.key; });
      axes.push_back(own != v.own_values.end() ? &*own : &a);
      per_variant *= axes.back()->values.size();
    }
    for (std::size_t k = 0; k < per_variant; ++k) {
      SweepPoint p;
      p.index = static_cast<int>(points.size());
      p.variant = &v;
      p.values.resize(axes.size());
      std::size_t rest = k;
      for (std::size_t a = axes.size(); a-- > 0;) {  // the last axis varies fastest
        p.values[a] = &axes[a]->values[rest % axes[a]->values.size()];
        rest /= axes[a]->values.size();
      }
      points.push_back(std::move(p));
    }
  }
  return points;
}

std::vector<SweepRun> sweep_runs(const SweepSpec& spec, const std::vector<SweepPoint>& points) {
  SpecReader r(spec.source);
  const Config base = load_config(spec.base, {});
  std::vector<SweepRun> runs;
  for (const SweepPoint& p : points) {
    std::vector<const SweepSetting*> settings;
    for (const SweepSetting& s : p.variant->settings) settings.push_back(&s);
    for (const SweepSetting* s : p.values) settings.push_back(s);
    std::vector<std::string> overrides;
    for (const SweepSetting* s : settings) overrides.push_back(s->key + "=" + s->value);
    std::string described;
    for (const SweepSetting* s : settings) described += (described.empty() ? "" : ", ") + s->key + " = " + s->value;
    Config point_config;
    try {
      point_config = load_config(spec.base, overrides);
    } catch (const InputError& e) {
      // "--set system.n: ..." -> "SWEEP:LINE: ..." for the setting at fault.
      std::string message = e.what();
      for (const SweepSetting* s : settings) {
        const std::string prefix = "--set " + s->key;
        if (message.rfind(prefix, 0) == 0) {
          std::string rest = message.substr(prefix.size());
          if (rest.rfind("=" + s->value, 0) == 0) rest = rest.substr(1 + s->value.size());
          if (rest.rfind(": ", 0) == 0) r.fail(s->line, rest.substr(2));
        }
      }
      // A rule between several settings: "--set a=1 --set b=2: ..." -> "grid point ...: ...".
      for (bool stripped = true; stripped;) {
        stripped = false;
        for (const std::string& o : overrides)
          for (const char* end : {" ", ": "})
            if (message.rfind("--set " + o + end, 0) == 0) {
              message = message.substr(6 + o.size() + std::string_view(end).size());
              stripped = true;
            }
      }
      r.fail(0, fmt::format("grid point {} ({}): {}", p.index, described.empty() ? "the base" : described, message));
    }
    // A seed in the grid starts the point's realizations; otherwise [sweep] seed_base does,
    // or the base configuration's initial.seed.
    const bool seed_in_grid =
        std::any_of(settings.begin(), settings.end(), [](const SweepSetting* s) { return s->key == "initial.seed"; });
    const std::uint64_t first_seed =
        seed_in_grid ? point_config.initial.seed : spec.seed_base.value_or(base.initial.seed);
    if (first_seed > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) - spec.realizations)
      r.fail(0, fmt::format("seed {} + {} realizations: seeds must stay below 2^63", first_seed, spec.realizations));
    for (int k = 0; k < spec.realizations; ++k) {
      SweepRun run;
      run.point = p.index;
      run.realization = k;
      run.seed = first_seed + static_cast<std::uint64_t>(k);
      run.name = fmt::format("p{:03d}-r{:02d}", p.index, k);
      run.config = point_config;
      run.config.initial.seed = run.seed;
      runs.push_back(std::move(run));
    }
  }
  return runs;
}

}  // namespace ballagg
