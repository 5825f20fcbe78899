#include "ballagg/config/set_override.hpp"

#include <algorithm>
#include <cstdint>
#include <string_view>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {
namespace {

// A --set argument as it can be shown on one line: control characters as \n, \t, \xNN.
std::string printable_argument(const std::string& arg) {
  std::string out;
  for (const char c : arg) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c == '\r') out += "\\r";
    else if (u < 0x20 || u == 0x7f) out += fmt::format("\\x{:02x}", u);
    else out += c;
  }
  return out;
}

// The offset of the first byte of `text` that does not belong to a well-formed UTF-8
// sequence (RFC 3629: no overlong forms, no surrogates, at most U+10FFFF), or npos.
std::size_t first_invalid_utf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto b = static_cast<unsigned char>(text[i]);
    const std::size_t length = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xe ? 3 : (b >> 3) == 0x1e ? 4 : 0;
    if (length == 0 || i + length > text.size()) return i;
    std::uint32_t code = length == 1 ? b : b & (0x7f >> length);
    for (std::size_t k = 1; k < length; ++k) {
      const auto c = static_cast<unsigned char>(text[i + k]);
      if ((c >> 6) != 0x2) return i;
      code = (code << 6) | (c & 0x3f);
    }
    constexpr std::uint32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (code < kSmallest[length] || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return i;
    i += length;
  }
  return std::string_view::npos;
}

// The same with every byte outside ASCII escaped too: for an argument that is not UTF-8,
// whose error line must itself be text.
std::string printable_ascii(const std::string& arg) {
  std::string out;
  for (const char c : printable_argument(arg)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x80) out += fmt::format("\\x{:02x}", u);
    else out += c;
  }
  return out;
}

// A control character (a newline, a tab, NUL...) in a --set would be read as the end of
// the TOML value, the rest of the argument silently dropped or taken as another key; bytes
// that are not UTF-8 would be accepted here and written into config.toml and summary.json,
// which every TOML and JSON reader (ours included) then refuses.
void refuse_unprintable(const std::string& arg) {
  const auto bad = std::find_if(arg.begin(), arg.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 || u == 0x7f;
  });
  if (bad != arg.end())
    throw InputError(fmt::format("--set \"{}\": control character {} in the argument (one section.key=value per --set, "
                                 "printable characters only)", printable_argument(arg),
                                 printable_argument(std::string(1, *bad))));
  if (const std::size_t at = first_invalid_utf8(arg); at != std::string_view::npos)
    throw InputError(fmt::format("--set {}: byte {} (0x{:02x}) is not UTF-8 text (arguments must be UTF-8)",
                                 printable_ascii(arg), at + 1, static_cast<unsigned char>(arg[at])));
}

}  // namespace

void apply_override(toml::table& root, const std::string& arg, std::set<std::string>& overridden) {
  refuse_unprintable(arg);
  const auto eq = arg.find('=');
  const std::string path = arg.substr(0, eq);
  const auto dot = path.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == path.size() ||
      path.find('.', dot + 1) != std::string::npos)
    throw InputError(fmt::format("--set {}: expected section.key=value (for example --set system.n=400)", arg));
  const std::string section = path.substr(0, dot), key = path.substr(dot + 1);
  const std::string text = arg.substr(eq + 1);
  toml::node* existing = root.get(section);
  if (existing == nullptr) existing = &root.insert_or_assign(section, toml::table{}).first->second;
  toml::table* table = existing->as_table();
  if (table == nullptr) throw InputError(fmt::format("--set {}: [{}] is not a table", arg, section));
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + text);
  } catch (const toml::parse_error&) {
    table->insert_or_assign(key, text);
    overridden.insert(path);
    return;
  }
  const toml::node& v = *parsed.get("v");
  if (auto i = v.value_exact<std::int64_t>()) table->insert_or_assign(key, *i);
  else if (auto d = v.value_exact<double>()) table->insert_or_assign(key, *d);
  else if (auto b = v.value_exact<bool>()) table->insert_or_assign(key, *b);
  else if (auto s = v.value_exact<std::string>()) table->insert_or_assign(key, *s);
  else if (const toml::array* a = v.as_array()) table->insert_or_assign(key, *a);
  else throw InputError(fmt::format("--set {}: the value must be a number, a boolean, a string or an array", arg));
  overridden.insert(path);
}

}  // namespace ballagg
