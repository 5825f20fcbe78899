// libFuzzer target: the TOML configuration reader (parse_config_text), as `ballagg run
// FILE` feeds it. Any input must give a Config or one InputError, never a crash, a hang
// or another exception; a Config that is accepted must round-trip through its resolved
// TOML text (what config.toml and checkpoints store) to the same text.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "ballagg/config/config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const ballagg::Config c = ballagg::parse_config_text(text, "fuzz.toml");
    const std::string resolved = ballagg::to_toml_text(c);
    if (ballagg::to_toml_text(ballagg::parse_config_text(resolved, "resolved.toml")) != resolved) std::abort();
  } catch (const ballagg::InputError&) {
  }
  return 0;
}
