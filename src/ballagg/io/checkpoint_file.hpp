#pragma once
// The checkpoint file of a run (RUN_DIR/checkpoint.bin), docs/checkpoints.md:
//
//   magic       16 bytes "BALLAGG CHECKPT\n"
//   version     uint32, kCheckpointFormat (raised whenever any section's layout changes)
//   byte order  uint32 0x01020304 as written by the machine that wrote the file
//   size        uint64, bytes of the payload
//   payload     sections (core/byte_stream.hpp encoding): program version, dimension, engine,
//               resolved configuration (TOML), wall seconds so far, then the opaque
//               sections of the run's parts (initial totals, state, engine, recorders)
//   crc32       uint32 of the payload (zlib)
//
// A file that is not exactly this (another program's file, an older format, a file cut
// short by a full disk, a flipped bit) is refused with one line saying which, never
// misread. decode_checkpoint is a function from bytes to a checkpoint or one
// CheckpointError, so that it can be fuzzed as it is.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "ballagg/core/byte_stream.hpp"

namespace ballagg {

inline constexpr std::uint32_t kCheckpointFormat = 2;
inline constexpr const char* kCheckpointFile = "checkpoint.bin";
// The largest checkpoint read (docs/checkpoints.md): 10^8 spheres at 2 KiB each, above
// what a sphere takes in any engine's checkpoint (the rigid-body engine's, with its bodies,
// the most). A file that is not a regular file, or is larger, is refused before it is read.
inline constexpr std::uint64_t kMaxCheckpointBytes = std::uint64_t{256} << 30;  // 256 GiB

struct Checkpoint {
  std::string program_version;  // of the ballagg that wrote it (for messages)
  int dimension = 2;
  std::string engine;           // Engine::name()
  std::string config_toml;      // the resolved configuration of the run
  double wall_seconds = 0.0;    // spent by the run up to the checkpoint
  std::string totals;           // the run's parts, each encoded by its owner
  std::string state;
  std::string engine_state;
  std::string timeseries;
  std::string snapshots;        // empty without a trajectory
};

// A section put by its owner straight into the file being written (the State, the
// engine's state: a few hundred bytes per sphere each, never held whole in memory).
using SectionWriter = std::function<void(ByteWriter&)>;

// The file's bytes (write_checkpoint_file writes the same without assembling them).
std::string encode_checkpoint(const Checkpoint& c);
// `source` names the bytes in messages (the file's path). Throws CheckpointError.
Checkpoint decode_checkpoint(std::string_view bytes, const std::string& source);

// dir/checkpoint.bin read and decoded. Throws CheckpointError (a missing file included).
Checkpoint read_checkpoint_file(const std::string& dir);
// Writes dir/checkpoint.bin atomically and durably: a temporary file, flushed to the disk
// (fsync), renamed over the previous checkpoint. A crash at any moment leaves either
// the previous checkpoint or the new one. Throws OutputError.
void write_checkpoint_file(const std::string& dir, const Checkpoint& checkpoint);
// The same file with the state and engine_state sections put by `state` and
// `engine_state` instead of taken from `checkpoint` (whose two are not read): the same
// bytes as when they hold what the writers put, streamed through a bounded buffer.
void write_checkpoint_file(const std::string& dir, const Checkpoint& checkpoint, const SectionWriter& state,
                           const SectionWriter& engine_state);

}  // namespace ballagg
