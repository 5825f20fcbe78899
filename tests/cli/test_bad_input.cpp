// The bad-input regression corpus, tests/bad_input/ (docs/hardening.md, "The bad-input
// corpus"): every case of its manifest cases.toml runs the binary in a fresh copy of the
// corpus directory and must end as bad input ends: status 2, exactly one line on stderr,
// `ballagg: error: ...` holding the case's expected text, nothing on stdout, no file
// created, changed or removed in the directory, within kCaseSeconds. Adding a case is
// adding its input file(s) and one line to cases.toml.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;

namespace {

// A bad input ends within this many seconds, a sanitized binary on a loaded machine
// included (measured: at most 0.1 s in Release and 0.31 s under ASan+UBSan at load
// average 5 on 2 cores; about 1 s in Release at load 19). A case is killed at twice this.
constexpr int kCaseSeconds = 5;

const fs::path kCorpus = fs::path(BALLAGG_SOURCE_DIR) / "tests" / "bad_input";
const fs::path kManifest = kCorpus / "cases.toml";

struct BadInputCase {
  std::string name;
  std::vector<std::string> args;
  std::vector<std::string> expect;  // each must occur in the error line
  std::string manifest_error;       // the manifest could not be read: the case reports why
};

void PrintTo(const BadInputCase& c, std::ostream* os) { *os << c.name; }

bool is_test_name(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char ch) { return std::isalnum(ch) || ch == '_'; });
}

// A list of strings: a TOML array of strings, or one string for a list of one.
std::optional<std::vector<std::string>> strings(const toml::node* node) {
  if (node == nullptr) return std::nullopt;
  if (auto s = node->value_exact<std::string>()) return std::vector<std::string>{*s};
  const toml::array* a = node->as_array();
  if (a == nullptr) return std::nullopt;
  std::vector<std::string> out;
  for (const toml::node& item : *a) {
    auto s = item.value_exact<std::string>();
    if (!s) return std::nullopt;
    out.push_back(*s);
  }
  return out;
}

std::vector<BadInputCase> read_manifest() {
  auto broken = [](const std::string& why) {
    return std::vector<BadInputCase>{{"manifest", {}, {}, kManifest.string() + ": " + why}};
  };
  toml::table root;
  try {
    root = toml::parse_file(kManifest.string());
  } catch (const toml::parse_error& e) {
    return broken(fmt::format("line {}: {}", e.source().begin.line, e.description()));
  }
  const toml::table* cases = root["cases"].as_table();
  if (cases == nullptr || root.size() != 1) return broken("expected one table [cases] and nothing else");
  std::vector<BadInputCase> out;
  for (auto&& [key, node] : *cases) {
    const std::string name(key.str());
    const toml::table* t = node.as_table();
    const std::string where = fmt::format("line {}: case {}", node.source().begin.line, name);
    if (!is_test_name(name)) return broken(where + ": a name is letters, digits and underscores");
    if (t == nullptr) return broken(where + ": expected { args = [...], expect = \"...\" }");
    const auto args = strings(t->get("args"));
    const auto expect = strings(t->get("expect"));
    if (!args || !expect || expect->empty() || t->size() != 2)
      return broken(where + ": expected { args = [...], expect = \"...\" } (args: strings; expect: a string or strings)");
    out.push_back({name, *args, *expect, ""});
  }
  if (out.empty()) return broken("no case");
  return out;
}

const std::vector<BadInputCase>& manifest() {
  static const std::vector<BadInputCase> cases = read_manifest();
  return cases;
}

// Every entry below `dir` (relative path -> what it is: a file's bytes, a link's target,
// or a directory), not following links.
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> entries;
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = fs::relative(it->path(), dir).string();
    if (it->is_symlink()) entries[name] = "link to " + fs::read_symlink(it->path()).string();
    else if (it->is_directory()) entries[name] = "directory";
    else if (it->is_regular_file()) entries[name] = "file: " + ballagg::testing::slurp(it->path());
    else entries[name] = "special file";
  }
  return entries;
}

std::string difference(const std::map<std::string, std::string>& before, const std::map<std::string, std::string>& after) {
  std::string d;
  for (const auto& [name, what] : after) {
    const auto was = before.find(name);
    if (was == before.end()) d += "  created: " + name + "\n";
    else if (was->second != what) d += "  changed: " + name + "\n";
  }
  for (const auto& [name, what] : before)
    if (!after.count(name)) d += "  removed: " + name + "\n";
  return d;
}

std::string command_line(const BadInputCase& c) {
  std::string s = "ballagg";
  for (const std::string& a : c.args) s += " " + ballagg::testing::quoted(a);
  return s;
}

class BadInput : public ::testing::TestWithParam<BadInputCase> {};

TEST_P(BadInput, IsOneLineStatus2AndWritesNothing) {
  const BadInputCase& c = GetParam();
  ASSERT_EQ(c.manifest_error, "");
  const ballagg::testing::TempDir scratch("ballagg-test-bad-input-");
  const fs::path work = scratch / "corpus";
  fs::copy(kCorpus, work, fs::copy_options::recursive | fs::copy_options::copy_symlinks);
  const auto before = tree(work);
  SCOPED_TRACE("in a copy of tests/bad_input: " + command_line(c));

  const ballagg::testing::Outcome o = ballagg::testing::run_ballagg_in(work, c.args, scratch.path(), 2 * kCaseSeconds);
  EXPECT_EQ(o.status, 2) << "stderr: " << o.err;
  EXPECT_LE(o.seconds, kCaseSeconds);
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << "stderr: " << o.err;
  EXPECT_TRUE(!o.err.empty() && o.err.back() == '\n') << "stderr: " << o.err;
  EXPECT_EQ(o.err.rfind("ballagg: error: ", 0), 0u) << "stderr: " << o.err;
  for (const std::string& needle : c.expect) EXPECT_CONTAINS(o.err, needle);
  EXPECT_EQ(o.out, "");
  EXPECT_EQ(difference(before, tree(work)), "") << "the command wrote into its directory";
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInput, ::testing::ValuesIn(manifest()),
                         [](const ::testing::TestParamInfo<BadInputCase>& param_info) { return param_info.param.name; });

// Every input file of the corpus is used by a case: named by an argument, itself or a
// directory holding it (checkpoint/truncated for checkpoint/truncated/checkpoint.bin).
TEST(BadInputCorpus, EveryFileBelongsToACase) {
  ASSERT_EQ(manifest().front().manifest_error, "");
  for (const auto& entry : fs::recursive_directory_iterator(kCorpus)) {
    if (entry.is_directory()) continue;
    const fs::path file = fs::relative(entry.path(), kCorpus);
    if (file == "cases.toml" || file.extension() == ".py") continue;
    bool used = false;
    for (fs::path p = file; !used && p.has_parent_path(); p = p.parent_path())
      for (const BadInputCase& c : manifest())
        for (const std::string& a : c.args) used = used || a.find(p.string()) != std::string::npos;
    EXPECT_TRUE(used) << "tests/bad_input/" << file.string() << " is named by no case of cases.toml";
  }
}

}  // namespace
