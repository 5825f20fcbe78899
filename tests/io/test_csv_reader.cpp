// The one CSV reader (io/csv_reader.hpp): strict rows and numbers, errors naming the file,
// the line and the column; and the readers built on it, which used to turn a bad field
// into a silent 0 (a sweep's gathered tables, verify's time series).
#include <filesystem>
#include <cmath>
#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "ballagg/core/input_error.hpp"
#include "ballagg/io/csv_reader.hpp"
#include "ballagg/sweep/sweep_runner.hpp"
#include "ballagg/sweep/sweep_spec.hpp"
#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using ballagg::CsvReader;
using ballagg::CsvRow;
using ballagg::InputError;
using ballagg::testing::TempDir;

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(CsvReader, SkipsCommentsAndBlankLinesAndTrimsFields) {
  const std::string text = "# a comment\n\n a , b\n1, 2.5\n\n# another\n-3 ,nan\r\n";
  CsvReader csv(text, "t.csv", "a,b");
  EXPECT_EQ(csv.header_line(), 3);
  ASSERT_EQ(csv.columns().size(), 2u);
  EXPECT_EQ(csv.columns()[0], "a");
  EXPECT_EQ(csv.column("b"), 1);
  EXPECT_EQ(csv.column("c"), -1);
  CsvRow row;
  ASSERT_TRUE(csv.next(row));
  EXPECT_EQ(row.line, 4);
  EXPECT_EQ(csv.number(row, 1), 2.5);
  ASSERT_TRUE(csv.next(row));
  EXPECT_EQ(row.line, 7);
  EXPECT_EQ(csv.integer(row, 0), -3);
  EXPECT_TRUE(std::isnan(csv.number(row, 1)));
  EXPECT_FALSE(csv.next(row));
}

TEST(CsvReader, ErrorsNameTheFileTheLineAndTheColumn) {
  EXPECT_EQ(error_of([] { CsvReader("\n# only a comment\n", "e.csv", "x,y"); }),
            "e.csv: empty file (expected a header line x,y)");
  const std::string short_row = "x,y\n1,2\n3\n";
  EXPECT_EQ(error_of([&] {
              CsvReader csv(short_row, "s.csv", "x,y");
              CsvRow row;
              while (csv.next(row)) {
              }
            }),
            "s.csv:3: 1 fields, but the header has 2");
  const std::string bad = "x,y\n1,2\n3,4O\n";
  EXPECT_EQ(error_of([&] {
              CsvReader csv(bad, "b.csv", "x,y");
              CsvRow row;
              while (csv.next(row)) csv.number(row, 1);
            }),
            "b.csv:3: column y: '4O' is not a number");
  EXPECT_EQ(error_of([&] {
              CsvReader csv(std::string_view("id\n2.5\n"), "i.csv", "id");
              CsvRow row;
              csv.next(row);
              csv.integer(row, 0);
            }),
            "i.csv:2: column id: '2.5' is not an integer");
}

TEST(CsvReader, ASweepRefusesARunTableWithAFieldThatIsNotANumber) {
  // A finished sweep whose run's box_counting.csv has a corrupted field: gathering the
  // tables again (resume) stops with the file and line, instead of averaging in a 0.
  TempDir dir;
  const fs::path out = dir / "sweep";
  const char* text = "[sweep]\nrealizations = 1\nseed_base = 40\n[grid]\nsystem.n = [16]\n";
  const ballagg::Communicator world;
  ballagg::SweepOptions o;
  o.out_dir = out.string();
  o.jobs = 1;
  o.quiet = true;
  ballagg::run_sweep(ballagg::parse_sweep_text(text, "s.toml"), o, world);
  const fs::path table = out / "runs" / "p000-r00" / "box_counting.csv";
  std::string csv = ballagg::testing::slurp(table);
  const std::size_t second_row = csv.find('\n', csv.find('\n') + 1) + 1;
  csv[second_row] = 'x';
  std::ofstream(table) << csv;
  o.resume = true;
  const std::string e = error_of([&] { ballagg::run_sweep(ballagg::parse_sweep_text(text, "s.toml"), o, world); });
  EXPECT_NE(e.find("box_counting.csv:3: column level: 'x"), std::string::npos) << e;
}
