#include "ballagg/run/verify_trajectory.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "ballagg/config/text_file.hpp"
#include "ballagg/io/h5md_reader.hpp"

namespace ballagg {
namespace {

// What the checks need of one frame.
struct FrameHeader {
  double time = 0.0;
  long long spheres = 0;
  double box = 0.0;    // the first cell edge
  double depth = 0.0;  // the third cell edge (XYZ: the box in 3D, a sphere's diameter in 2D)
};

class Findings {
 public:
  Findings(Verification& out, std::string file) : out_(out), file_(std::move(file)) {}
  void check(bool holds, const std::string& violation) {
    ++out_.checks;
    if (!holds) out_.violations.push_back(fmt::format("{}: {}", file_, violation));
  }

 private:
  Verification& out_;
  std::string file_;
};

// The value of KEY="..." or KEY=... in an extended-XYZ comment line.
std::optional<std::string> xyz_field(const std::string& comment, const std::string& key) {
  const std::size_t at = comment.find(key + "=");
  if (at == std::string::npos) return std::nullopt;
  std::size_t begin = at + key.size() + 1;
  if (begin < comment.size() && comment[begin] == '"') {
    const std::size_t end = comment.find('"', begin + 1);
    if (end == std::string::npos) return std::nullopt;
    return comment.substr(begin + 1, end - begin - 1);
  }
  return comment.substr(begin, comment.find(' ', begin) - begin);
}

// Every frame's header of trajectory.xyz; a file that is not made of frames is one
// violation, and whatever was read before it is returned.
std::vector<FrameHeader> xyz_headers(const std::string& path, Findings& f) {
  check_input_file(path, "trajectory", std::numeric_limits<std::uint64_t>::max());
  std::ifstream in(path, std::ios::binary);
  std::vector<FrameHeader> frames;
  std::string count, comment, row;
  while (std::getline(in, count)) {
    FrameHeader h;
    char* end = nullptr;
    h.spheres = std::strtoll(count.c_str(), &end, 10);
    std::getline(in, comment);
    const std::optional<std::string> lattice = xyz_field(comment, "Lattice"), time = xyz_field(comment, "Time");
    std::istringstream cell(lattice.value_or(""));
    double e[9] = {};
    for (double& v : e) cell >> v;
    if (end == count.c_str() || *end != '\0' || h.spheres < 0 || !time || !lattice || cell.fail()) {
      f.check(false, fmt::format("frame {} is not an extended-XYZ frame of ballagg (no sphere count, Lattice or Time)",
                                 frames.size()));
      return frames;
    }
    h.time = std::strtod(time->c_str(), nullptr);
    h.box = e[0];
    h.depth = e[8];
    for (long long i = 0; i < h.spheres; ++i)
      if (!std::getline(in, row)) {
        f.check(false, fmt::format("frame {} is cut short ({} of {} spheres)", frames.size(), i, h.spheres));
        return frames;
      }
    frames.push_back(h);
  }
  return frames;
}

template <int D>
std::vector<FrameHeader> h5md_headers(const std::string& path, Findings& f) {
  check_input_file(path, "trajectory", std::numeric_limits<std::uint64_t>::max());
  std::vector<FrameHeader> frames;
  try {
    const H5mdReader<D> reader(path);
    for (double t : reader.times()) {
      FrameHeader h;
      h.time = t;
      h.spheres = reader.particles().size();
      h.box = reader.particles().box.length;
      h.depth = D == 3 ? h.box : 0.0;
      frames.push_back(h);
    }
  } catch (const InputError& e) {
    // A trajectory of the other dimension, or no ballagg trajectory at all.
    f.check(false, e.what());
  }
  return frames;
}

// The frames against the run: spheres, box, dimension, and times.
template <int D>
void check_frames(const std::vector<FrameHeader>& frames, const Config& c, double final_time, int spheres,
                  double depth, Findings& f) {
  if (frames.empty()) return;
  const double box = resolved_box_length(c);
  const double every = c.output.snapshot_every;
  std::size_t wrong_count = 0, wrong_box = 0, wrong_depth = 0, disorder = 0, off_schedule = 0;
  std::string first_wrong_count, first_disorder, first_off;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const FrameHeader& h = frames[k];
    if (spheres > 0 && h.spheres != spheres && wrong_count++ == 0)
      first_wrong_count = fmt::format("frame {} has {}", k, h.spheres);
    if (h.box != box) ++wrong_box;
    if (depth > 0.0 && h.depth != depth) ++wrong_depth;
    if (k > 0 && !(h.time > frames[k - 1].time) && disorder++ == 0)
      first_disorder = fmt::format("frame {} at t = {} after frame {} at t = {}", k, h.time, k - 1, frames[k - 1].time);
    // The initial state at 0, frame k at k * every; the last is the final state.
    const bool last = k + 1 == frames.size();
    const double due = static_cast<double>(k) * every;
    if (!last && h.time != due && off_schedule++ == 0)
      first_off = fmt::format("frame {} at t = {}, where output.snapshot_every = {} puts it at t = {}", k, h.time, every, due);
  }
  if (spheres > 0)
    f.check(wrong_count == 0, fmt::format("{} frame(s) with another number of spheres than the run's {} ({})",
                                          wrong_count, spheres, first_wrong_count));
  f.check(wrong_box == 0, fmt::format("{} frame(s) in another box than the run's side {}", wrong_box, box));
  if (depth > 0.0)
    f.check(wrong_depth == 0, fmt::format("{} frame(s) of another dimension or cell than the run's {}D", wrong_depth, D));
  f.check(disorder == 0, fmt::format("{} frame(s) out of time order or repeated ({})", disorder, first_disorder));
  f.check(off_schedule == 0, fmt::format("{} frame(s) not at the run's snapshot times ({}): frames of another run?",
                                         off_schedule, first_off));
  f.check(frames.back().time == final_time,
          fmt::format("the last frame is at t = {}, the run ended at t = {} (summary.json)", frames.back().time, final_time));
}

}  // namespace

template <int D>
void verify_trajectories(const RunDirectory& run, double final_time, int spheres, double largest_radius,
                         Verification& out) {
  const Config& c = run.config;
  for (const SnapshotFormat format : {SnapshotFormat::xyz, SnapshotFormat::h5md}) {
    const std::string name = format == SnapshotFormat::h5md ? "trajectory.h5md" : "trajectory.xyz";
    const std::string path = run.path(name);
    std::error_code ec;
    if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) continue;
    Findings f(out, name);
    const bool configured = c.output.snapshot_every > 0.0 &&
                            std::find(c.output.snapshot_formats.begin(), c.output.snapshot_formats.end(), format) !=
                                c.output.snapshot_formats.end();
    f.check(configured, "config.toml writes no such trajectory (output.snapshot_every, output.snapshot_formats): the "
                        "file of another run");
    if (!configured) continue;
    if (format == SnapshotFormat::xyz) {
      const double depth = D == 3 ? resolved_box_length(c) : 2.0 * largest_radius;
      check_frames<D>(xyz_headers(path, f), c, final_time, spheres, spheres > 0 ? depth : 0.0, f);
    } else {
      check_frames<D>(h5md_headers<D>(path, f), c, final_time, spheres, 0.0, f);
    }
  }
}

template void verify_trajectories<2>(const RunDirectory&, double, int, double, Verification&);
template void verify_trajectories<3>(const RunDirectory&, double, int, double, Verification&);

}  // namespace ballagg
