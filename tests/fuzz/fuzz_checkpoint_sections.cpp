// libFuzzer target: everything `ballagg run --resume` decodes from a checkpoint before it
// writes anything, behind the file's CRC-32 (which stops a fuzzer at fuzz_checkpoint's
// level). The input is a checkpoint's payload (docs/checkpoints.md); the harness adds the
// header and the CRC, so every mutation reaches the section decoders: the resolved
// configuration (TOML), the State (StateCodec), the engine's own state
// (Engine::resume_from, every engine that supports checkpoints) and the time series.
// Any bytes must be accepted or refused with one InputError / CheckpointError.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "ballagg/config/config.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/state_codec.hpp"
#include "ballagg/io/checkpoint_file.hpp"
#include "ballagg/io/timeseries.hpp"
#include "ballagg/run/simulation.hpp"
#include "checkpoint_payload.hpp"

namespace {

// What run_in_dimension does with a checkpoint before its first output.
template <int D>
void restore(const ballagg::Checkpoint& c, const ballagg::Config& config) {
  ballagg::State<D> state = ballagg::StateCodec<D>::decode(c.state);
  const std::unique_ptr<ballagg::Engine<D>> engine = ballagg::make_engine<D>(config);
  if (c.engine != engine->name() || !engine->supports_checkpoints()) return;
  engine->resume_from(state, c.engine_state);
  ballagg::TimeseriesRecorder<D> timeseries(config.output.timeseries_interval,
                                            config.engine.kind == ballagg::EngineKind::rigid_body);
  timeseries.restore(c.timeseries);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const ballagg::Checkpoint c =
        ballagg::decode_checkpoint(ballagg::testing::checkpoint_file_of({reinterpret_cast<const char*>(data), size}), "fuzz.bin");
    const ballagg::Config config = ballagg::parse_config_text(c.config_toml, "fuzz.bin");
    if (config.system.dimension != c.dimension) return 0;
    if (c.dimension == 2) restore<2>(c, config);
    else restore<3>(c, config);
  } catch (const ballagg::InputError&) {
  }
  return 0;
}
