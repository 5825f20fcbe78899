// libFuzzer target: `--set` strings, as `ballagg run --set A --set B ...` hands them to
// load_config: the input is split at NUL bytes (which no argument can hold) into up to
// kMaxOverrides overrides of the defaults. Any input must give a Config or one
// InputError, never a crash, a hang or another exception. An accepted config
//   * round-trips through its resolved TOML (`to_toml_text`, what config.toml and
//     checkpoints store) to the same text;
//   * is the same when the overrides are applied again to that text (what
//     `ballagg config --set ... > c.toml; ballagg run c.toml --set ...` gives);
//   * holds every accepted override whole: a value read as TOML ("v = VALUE") yields that
//     one value, so that no part of an argument (text after a line break) is dropped unread.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "ballagg/config/config.hpp"

namespace {

constexpr std::size_t kMaxOverrides = 16;  // a longer command line tests nothing new

// The TOML document that apply_override reads a value from holds that value alone.
void expect_value_read_whole(const std::string& override_text) {
  const std::size_t eq = override_text.find('=');
  if (eq == std::string::npos) std::abort();  // accepted without '='
  try {
    const toml::table value = toml::parse("v = " + override_text.substr(eq + 1));
    if (value.size() != 1) std::abort();  // the argument held more than its value
  } catch (const toml::parse_error&) {
    // taken as a bare string (engine.kind=ed): the whole text
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> overrides;
  std::string current;
  for (std::size_t k = 0; k < size; ++k) {
    if (data[k] == 0) {
      overrides.push_back(current);
      current.clear();
    } else {
      current.push_back(static_cast<char>(data[k]));
    }
  }
  if (size > 0) overrides.push_back(current);
  if (overrides.size() > kMaxOverrides) return 0;
  ballagg::Config c;
  try {
    c = ballagg::load_config("", overrides);
  } catch (const ballagg::InputError&) {
    return 0;
  }
  for (const std::string& o : overrides) expect_value_read_whole(o);
  const std::string resolved = ballagg::to_toml_text(c);
  try {
    if (ballagg::to_toml_text(ballagg::parse_config_text(resolved, "resolved.toml")) != resolved) std::abort();
    if (ballagg::to_toml_text(ballagg::parse_config_text(resolved, "resolved.toml", overrides)) != resolved) std::abort();
  } catch (const ballagg::InputError&) {
    std::abort();  // an accepted configuration whose own text is refused
  }
  return 0;
}
