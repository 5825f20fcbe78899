// libFuzzer target: a configuration and a state file together, through everything
// `ballagg run` does before it writes anything: parse_config_text, make_initial_state
// (which reads initial.file), resolve_defaults, stop_criteria and make_engine. The input
// is CONFIG TEXT, a NUL byte, STATE TEXT; when the configuration has
// initial.positions = "file", initial.file names a temporary file holding the state text
// (whatever name the configuration gave). Any input must end in one InputError or a
// ready engine, never a crash, an out-of-bounds read, a hang or a wild allocation; the
// resolved configuration (written to config.toml and checkpoints, read back by
// --resume) must be accepted again and round-trip to the same text.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>

#include "ballagg/config/config.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/run/simulation.hpp"

namespace {

// Configurations that place their own spheres (lattice, random) are fuzzed up to this
// many: the state file is the point of this target, and a random placement of millions
// of spheres is a long run, not a finding.
constexpr std::int64_t kMaxGeneratedSpheres = 256;

// The state file of this process, removed when it exits (before the name is destroyed:
// exit handlers run in the reverse order of their registration).
const std::string& state_path() {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("fuzz_state_and_config-" + std::to_string(getpid()) + ".csv")).string();
  static const bool removed_at_exit = std::atexit([] { std::filesystem::remove(path); }) == 0;
  (void)removed_at_exit;
  return path;
}

template <int D>
void prepare_run(const ballagg::Config& c) {
  const ballagg::State<D> initial = ballagg::make_initial_state<D>(c);
  const ballagg::Config resolved = ballagg::resolve_defaults(c, initial);
  ballagg::stop_criteria(resolved);
  const std::unique_ptr<ballagg::Engine<D>> engine = ballagg::make_engine<D>(resolved);
  if (!engine) std::abort();
  const std::string text = ballagg::to_toml_text(resolved);
  try {
    if (ballagg::to_toml_text(ballagg::parse_config_text(text, "config.toml")) != text) std::abort();
  } catch (const ballagg::InputError&) {
    std::abort();  // a run whose own config.toml would be refused
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = input.find('\0');
  const std::string_view config_text = input.substr(0, nul);
  const std::string_view state_text = nul == std::string_view::npos ? std::string_view{} : input.substr(nul + 1);
  try {
    ballagg::Config c = ballagg::parse_config_text(config_text, "fuzz.toml");
    if (c.initial.positions == ballagg::InitialPositions::file) {
      std::ofstream(state_path(), std::ios::binary | std::ios::trunc) << state_text;
      c.initial.file = state_path();
    } else if (c.system.n > kMaxGeneratedSpheres) {
      return 0;
    }
    if (c.system.dimension == 2) prepare_run<2>(c);
    else prepare_run<3>(c);
  } catch (const ballagg::InputError&) {
  }
  return 0;
}
