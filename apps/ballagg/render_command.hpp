#pragma once
// `ballagg render RUN_DIR`: pictures, POV-Ray scenes and videos of a finished run.
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace ballagg::cli {

struct RenderArgs {
  std::string run_dir;
  std::optional<int> frame;
  std::string png, svg, pov, video;
  int width = 1200;
  double fps = 10.0;
  std::optional<int> aggregate;
  std::vector<double> view, light;
  bool quiet = false;  // no progress of a video's frames
};

struct RenderCommand {
  CLI::App* command = nullptr;
  RenderArgs args;
};

void add_render_command(CLI::App& app, RenderCommand& render);
// Throws InputError for bad arguments or unreadable run files; returns the exit status.
int run_render_command(const RenderCommand& command);

}  // namespace ballagg::cli
