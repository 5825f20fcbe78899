// What a new run that failed takes away from its directory (run_files.hpp): the files
// ballagg writes in a run directory and their temporary files, and nothing else.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "ballagg/run/run_files.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

TEST(RunFiles, RemoveRunFilesTakesOnlyTheFilesBallaggWrites) {
  testing::TempDir dir;
  for (const char* name : {"checkpoint.bin", ".trajectory.xyz.tmp", ".trajectory.h5md.tmp", "timeseries.csv",
                           "notes.txt", "final.csv.bak"})
    dir.write(name, "x");
  std::filesystem::create_directory(dir / "sub");
  remove_run_files(dir.path().string());
  for (const char* gone : {"checkpoint.bin", ".trajectory.xyz.tmp", ".trajectory.h5md.tmp", "timeseries.csv"})
    EXPECT_FALSE(std::filesystem::exists(dir / gone)) << gone;
  for (const char* kept : {"notes.txt", "final.csv.bak", "sub"}) EXPECT_TRUE(std::filesystem::exists(dir / kept)) << kept;
}

}  // namespace
}  // namespace ballagg
