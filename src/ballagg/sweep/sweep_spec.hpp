#pragma once
// A sweep file (docs/sweeps.md): a base configuration, a grid of values per dotted
// configuration key, optional variants (sets of keys that go together, such as an engine
// and its settings), and a number of realizations with different seeds. Read and checked
// completely before anything runs; every error names the sweep file's line.
#include <cstdint>
#include <string>
#include <vector>

#include "ballagg/config/config.hpp"

namespace ballagg {

// One setting: "section.key" and its value as --set text (TOML syntax), with the sweep
// file line it came from.
struct SweepSetting {
  std::string key;
  std::string value;
  int line = 0;
};

struct SweepAxis {
  std::string key;
  std::vector<SweepSetting> values;  // each with its own line
};

struct SweepVariant {
  std::string label;                  // the `label` key, or the settings joined
  std::vector<SweepSetting> settings;
  // Arrays in a variant replace the values of a grid key for that variant only (e.g. the
  // costly per-sphere models on the smaller N).
  std::vector<SweepAxis> own_values;
  int line = 0;  // of its [[variants]]; 0 for the one empty variant of a sweep without
};

struct SweepSpec {
  std::string source;            // the sweep file's path, for messages
  std::string text;              // its content (a resumed sweep must be started from the same)
  std::string base;              // the base configuration file (resolved path), empty: defaults
  int realizations = 1;
  std::optional<std::uint64_t> seed_base;  // default: the base configuration's initial.seed
  std::vector<SweepVariant> variants;      // at least one (possibly empty)
  std::vector<SweepAxis> axes;             // in file order; the first varies slowest
};

// One grid point: a variant and one value per axis (of the grid, or the variant's own).
struct SweepPoint {
  int index = 0;
  const SweepVariant* variant = nullptr;
  std::vector<const SweepSetting*> values;  // one per axis
};

struct SweepRun {
  int point = 0;
  int realization = 0;
  std::uint64_t seed = 0;
  std::string name;   // run directory under runs/: p007-r03
  Config config;
};

SweepSpec parse_sweep_text(const std::string& text, const std::string& source);
SweepSpec load_sweep(const std::string& path);

// Whether the sweep file has [[variants]] (without, the sweep has one empty variant).
bool has_variants(const SweepSpec& spec);

// Every point of the sweep: for each variant its grid (the first axis slowest).
std::vector<SweepPoint> sweep_points(const SweepSpec& spec);

// Every run (point-major, realizations inner), each configuration built and checked
// (throws InputError naming the sweep file line of the offending value, or the base file's).
std::vector<SweepRun> sweep_runs(const SweepSpec& spec, const std::vector<SweepPoint>& points);

}  // namespace ballagg
