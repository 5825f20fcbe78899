#include "ballagg/config/ts_section.hpp"

#include <cstdint>

#include <fmt/format.h>

#include "ballagg/config/section_reader.hpp"
#include "ballagg/config/value_ranges.hpp"
#include "ballagg/core/input_error.hpp"

namespace ballagg {
namespace {

// The keys of the engine's own additions, which ts.method = "paper" does not have.
constexpr const char* kKeysOfOurMethod[] = {"fall_back", "retreat_overlap", "retreat_pairs", "sweep_reuse_margin",
                                            "bond_stretch"};

// ts.method = "paper" runs the per-sphere models of §3.1 and §3.3 as printed: the rigid
// model is ours, and the keys of our additions would have no effect, so both are refused.
void refuse_what_the_paper_has_not(SectionReader& ts, TsModel model) {
  if (model == TsModel::rigid)
    ts.refuse("method", "needs ts.model = \"non-rigid\" (3.5) or \"almost-rigid\" (3.30)-(3.31); the rigid model "
                        "(the default) is not in the paper");
  for (const char* key : kKeysOfOurMethod)
    if (ts.has(key))
      ts.refuse("method", fmt::format("the paper's method has no fall-back, rigid remainder or bond cap: ts.{} has no "
                                      "effect with it (remove it, or use ts.method = \"ours\")", key));
}

}  // namespace

TimeSteppingSettings read_ts_section(const toml::table& root, const std::string& source,
                                     const std::set<std::string>& overridden) {
  TimeSteppingSettings t;
  DahaParameters& d = t.daha;
  SectionReader ts(root, "ts", source, overridden);
  auto in_open_unit = [](double v) { return v > 0.0 && v < 1.0; };
  if (auto v = ts.choice("model", {"rigid", "almost-rigid", "non-rigid"})) t.model = static_cast<TsModel>(*v);
  if (auto v = ts.choice("method", {"ours", "paper"})) t.method = static_cast<TsMethod>(*v);
  if (t.method == TsMethod::paper) refuse_what_the_paper_has_not(ts, t.model);
  // Each model's own (the paper's method: with (3.29) active); the keys below override them.
  d = t.method == TsMethod::paper ? paper_daha(t.model) : default_daha(t.model);
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
  if (d.c_min > d.c_max) {
    // Named by the --set that gave one of them, if one did.
    const std::string origin = overridden.count("ts.c_max") ? "--set ts.c_max"
                               : overridden.count("ts.c_min") ? "--set ts.c_min" : source;
    throw InputError(fmt::format("{}: ts.c_min = {} is larger than ts.c_max = {}: the damping bounds must satisfy c_min <= c_max",
                                 origin, d.c_min, d.c_max));
  }
  return t;
}

}  // namespace ballagg
