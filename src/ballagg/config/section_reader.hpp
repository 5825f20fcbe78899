#pragma once
// The reader of one section of a configuration's TOML document, shared by the readers of
// the sections (config.cpp, ts_section.cpp, rigid_body_section.cpp).
#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {

// Reads one section of the TOML document, remembering which keys it was asked for so
// that anything else is reported as unknown. Every error names where the value came from.
class SectionReader {
 public:
  SectionReader(const toml::table& root, std::string section, const std::string& source,
                const std::set<std::string>& overridden)
      : section_(std::move(section)), source_(source), overridden_(overridden) {
    if (const toml::node* node = root.get(section_)) {
      table_ = node->as_table();
      if (table_ == nullptr) {
        const std::string where = node->source().begin.line > 0
                                      ? fmt::format("{}:{}", source_, node->source().begin.line)
                                      : source_;
        std::ostringstream type;
        type << node->type();
        throw InputError(fmt::format("{}: {} must be a section ([{}]), but it is a value of type {}", where,
                                     section_, section_, type.str()));
      }
    }
  }

  std::optional<std::int64_t> integer(const std::string& key, std::int64_t lo, std::int64_t hi,
                                      const std::string& allowed) {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    std::optional<std::int64_t> v;
    if (auto i = node->value_exact<std::int64_t>()) v = *i;
    else if (auto d = node->value_exact<double>(); d && std::isfinite(*d) && *d == std::floor(*d) && std::abs(*d) < 9e18)
      v = static_cast<std::int64_t>(*d);  // 1e4 from the command line is an integer
    if (!v || *v < lo || *v > hi) fail(*node, key, allowed);
    return v;
  }

  // A finite number (or +inf when allow_infinite) accepted by `ok`.
  std::optional<double> real(const std::string& key, const std::function<bool(double)>& ok,
                             const std::string& allowed, bool allow_infinite = false) {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    std::optional<double> v;
    if (auto d = node->value_exact<double>()) v = *d;
    else if (auto i = node->value_exact<std::int64_t>()) v = static_cast<double>(*i);
    if (!v || std::isnan(*v) || (std::isinf(*v) && !(allow_infinite && *v > 0)) || !ok(*v))
      fail(*node, key, allowed);
    return v;
  }

  // A list of 1 to max_count finite numbers (a TOML array, or one number for a list of
  // one), each accepted by `ok`.
  std::optional<std::vector<double>> reals(const std::string& key, const std::function<bool(double)>& ok,
                                           std::size_t max_count, const std::string& allowed) {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    const std::vector<const toml::node*> items = items_of(*node);
    if (items.empty() || items.size() > max_count) fail(*node, key, allowed);
    std::vector<double> values;
    for (const toml::node* item : items) {
      std::optional<double> v;
      if (auto d = item->value_exact<double>()) v = *d;
      else if (auto i = item->value_exact<std::int64_t>()) v = static_cast<double>(*i);
      if (!v || !std::isfinite(*v) || !ok(*v)) fail(*node, key, allowed);
      values.push_back(*v);
    }
    return values;
  }

  std::optional<bool> boolean(const std::string& key) {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    auto b = node->value_exact<bool>();
    if (!b) fail(*node, key, "must be true or false");
    return b;
  }

  std::optional<std::string> string(const std::string& key, const std::string& allowed) {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    auto s = node->value_exact<std::string>();
    if (!s) fail(*node, key, allowed);
    return s;
  }

  // One of `names`; returns its index.
  std::optional<int> choice(const std::string& key, const std::vector<std::string>& names) {
    std::string allowed = "must be one of";
    for (std::size_t k = 0; k < names.size(); ++k) allowed += (k ? ", \"" : " \"") + names[k] + "\"";
    auto s = string(key, allowed);
    if (!s) return std::nullopt;
    for (std::size_t k = 0; k < names.size(); ++k)
      if (*s == names[k]) return static_cast<int>(k);
    fail(*find(key), key, allowed);
  }

  // A list of distinct names from `names` (a TOML array, or one string for a list of one);
  // returns their indices in the order given.
  std::optional<std::vector<int>> choices(const std::string& key, const std::vector<std::string>& names) {
    std::string allowed = "must be a list of distinct names from";
    for (std::size_t k = 0; k < names.size(); ++k) allowed += (k ? ", \"" : " \"") + names[k] + "\"";
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    const std::vector<const toml::node*> items = items_of(*node);
    std::vector<int> picked;
    for (const toml::node* item : items) {
      auto s = item->value_exact<std::string>();
      const auto it = s ? std::find(names.begin(), names.end(), *s) : names.end();
      const int index = static_cast<int>(it - names.begin());
      if (it == names.end() || std::find(picked.begin(), picked.end(), index) != picked.end()) fail(*node, key, allowed);
      picked.push_back(index);
    }
    return picked;
  }

  // Reports the first key of the section that nobody asked for.
  void reject_unknown_keys() const {
    if (table_ == nullptr) return;
    for (auto&& [k, node] : *table_) {
      const std::string key(k.str());
      if (!known_.count(key)) {
        std::string allowed;
        for (const std::string& a : known_) allowed += (allowed.empty() ? "" : ", ") + a;
        throw InputError(fmt::format("{}: unknown key '{}.{}' (keys of [{}]: {})", where(node, key), section_,
                                     key, section_, allowed));
      }
    }
  }

  // Whether the section gives `key` (in the file or with --set; which counts as asked for).
  bool has(const std::string& key) { return find(key) != nullptr; }

  // Refuses the value given for `key` (a rule that involves other keys too).
  [[noreturn]] void refuse(const std::string& key, const std::string& allowed) { fail(*find(key), key, allowed); }

  [[noreturn]] void fail(const toml::node& node, const std::string& key, const std::string& allowed) const {
    std::ostringstream value;
    if (node.is_string()) value << '"' << *node.value<std::string>() << '"';
    else if (auto d = node.value_exact<double>()) value << fmt::format("{}", *d);  // shortest form: 1e-09
    else if (const toml::array* a = node.as_array()) {
      value << '[';
      for (std::size_t k = 0; k < a->size(); ++k) {
        const toml::node& item = *a->get(k);
        value << (k ? ", " : "");
        if (item.is_string()) value << '"' << *item.value<std::string>() << '"';
        else if (item.is_value()) item.visit([&](auto&& v) { value << v; });
        else value << "<" << item.type() << ">";
      }
      value << ']';
    }
    else if (node.is_value()) node.visit([&](auto&& v) { value << v; });
    else value << "<" << node.type() << ">";
    throw InputError(fmt::format("{}: {}.{} = {}: {}", where(node, key), section_, key, value.str(), allowed));
  }

  // "<where>: section.key", the name an error about the value of key gives it.
  std::string name_of(const std::string& key) {
    const toml::node* node = find(key);
    return node == nullptr ? section_ + "." + key : fmt::format("{}: {}.{}", where(*node, key), section_, key);
  }

  std::string where(const toml::node& node, const std::string& key) const {
    if (overridden_.count(section_ + "." + key)) return "--set " + section_ + "." + key;
    if (node.source().begin.line > 0) return fmt::format("{}:{}", source_, node.source().begin.line);
    return source_;
  }

 private:
  // The items of a list key: a TOML array's elements, or the one value given for a list of one.
  static std::vector<const toml::node*> items_of(const toml::node& node) {
    std::vector<const toml::node*> items;
    if (const toml::array* a = node.as_array()) {
      for (const toml::node& item : *a) items.push_back(&item);
    } else {
      items.push_back(&node);
    }
    return items;
  }

  const toml::node* find(const std::string& key) {
    known_.insert(key);
    return table_ == nullptr ? nullptr : table_->get(key);
  }

  std::string section_;
  const std::string& source_;
  const std::set<std::string>& overridden_;
  const toml::table* table_ = nullptr;
  std::set<std::string> known_;
};

inline constexpr auto positive = [](double v) { return v > 0.0; };

// A value that passed its key's sign check but lies outside the magnitudes the engines'
// arithmetic handles (value_ranges.hpp) is refused with that range.
inline void refuse_outside(SectionReader& r, const std::string& key, std::optional<double> v, double lo, double hi,
                    const std::string& allowed) {
  if (v && (*v < lo || *v > hi)) r.refuse(key, allowed);
}

}  // namespace ballagg
