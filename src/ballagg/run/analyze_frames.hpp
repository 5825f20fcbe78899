#pragma once
// `ballagg analyze RUN_DIR --frames`: every indicator of `ballagg analyze` at each frame of
// the run's trajectory.h5md (or at the frames nearest given times), written as tables
// against time (io/frame_analysis_tables.hpp).
#include <string>
#include <vector>

namespace ballagg {

struct AnalyzeFramesRequest {
  std::string run_dir;
  std::string out_dir;       // default: RUN_DIR
  std::vector<double> times; // empty: every frame; else the frame nearest each time
};

// Throws InputError (one line) before writing anything when the run has no trajectory or a
// time is not a finite number. Returns the directory written to; `frames` gets the number
// of frames analysed.
std::string analyze_frames(const AnalyzeFramesRequest& request, int& frames);

// The frame nearest each time of `wanted` among frames at `times` (ascending), the earlier
// on a tie, each frame once, in time order.
std::vector<int> frames_nearest(const std::vector<double>& times, const std::vector<double>& wanted);

}  // namespace ballagg
