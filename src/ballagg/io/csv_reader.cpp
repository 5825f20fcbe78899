#include "ballagg/io/csv_reader.hpp"

#include <charconv>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

void split(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    out.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) return;
    start = comma + 1;
  }
}

template <typename T>
bool parse(std::string_view f, T& value) {
  const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), value);
  return ec == std::errc() && end == f.data() + f.size() && !f.empty();
}

}  // namespace

CsvReader::CsvReader(std::string_view text, std::string source, std::string expected_header)
    : text_(text), source_(std::move(source)) {
  std::string_view line;
  if (!next_line(line)) throw InputError(fmt::format("{}: empty file (expected a header line {})", source_, expected_header));
  header_line_ = line_no_;
  std::vector<std::string_view> names;
  split(line, names);
  for (std::string_view n : names) columns_.emplace_back(n);
}

bool CsvReader::next_line(std::string_view& line) {
  while (position_ < text_.size()) {
    const std::size_t end = text_.find('\n', position_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line = trim(text_.substr(position_, stop - position_));
    position_ = stop + 1;
    ++line_no_;
    if (!line.empty() && line.front() != '#') return true;
  }
  return false;
}

int CsvReader::column(std::string_view name) const {
  for (std::size_t k = 0; k < columns_.size(); ++k)
    if (columns_[k] == name) return static_cast<int>(k);
  return -1;
}

bool CsvReader::next(CsvRow& row) {
  std::string_view line;
  if (!next_line(line)) return false;
  row.line = line_no_;
  split(line, row.fields);
  if (row.fields.size() != columns_.size())
    throw InputError(
        fmt::format("{}:{}: {} fields, but the header has {}", source_, line_no_, row.fields.size(), columns_.size()));
  return true;
}

double CsvReader::number(const CsvRow& row, int column) const {
  double v = 0.0;
  const std::string_view f = row.fields[column];
  if (!parse(f, v))
    throw InputError(fmt::format("{}:{}: column {}: '{}' is not a number", source_, row.line, columns_[column], f));
  return v;
}

long long CsvReader::integer(const CsvRow& row, int column) const {
  long long v = 0;
  const std::string_view f = row.fields[column];
  if (!parse(f, v))
    throw InputError(fmt::format("{}:{}: column {}: '{}' is not an integer", source_, row.line, columns_[column], f));
  return v;
}

}  // namespace ballagg
