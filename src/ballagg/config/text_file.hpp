#pragma once
// Reading a whole input file, with the one-line errors of bad input. Only a regular file
// (or a link to one) is read, and only up to a stated size: a directory, a device such as
// /dev/zero, a FIFO or a socket would give no end or no sense, and is refused before any
// byte is read (docs/hardening.md, "Input files").
#include <cstdint>
#include <string>

namespace ballagg {

// Size limits of input files, far above any file of a real run (docs/hardening.md).
// Configuration and sweep files, a run's summary.json and the copy of its sweep file.
inline constexpr std::uint64_t kMaxSettingsFileBytes = std::uint64_t{16} << 20;  // 16 MiB
// State files (initial.file, final.csv) and a run's tables (timeseries.csv): 10^8 spheres
// at up to 640 bytes a row (a 3D rigid-body row of 13 round-trip numbers is under 350).
inline constexpr std::uint64_t kMaxStateFileBytes = std::uint64_t{64} << 30;  // 64 GiB

// The contents of `path`. Throws InputError "PATH: cannot read the WHAT: reason" when it is
// missing or unreadable, not a regular file (a directory, a device, a FIFO, a socket, a
// link to one) or larger than `max_bytes`.
std::string read_text_file(const std::string& path, const std::string& what, std::uint64_t max_bytes);

// The same checks without reading: throws as read_text_file would for a file that is not
// a regular file or is larger than `max_bytes` (a missing file passes).
void check_input_file(const std::string& path, const std::string& what, std::uint64_t max_bytes);

}  // namespace ballagg
