#pragma once
// The one reader of the CSV files ballagg reads: state files (initial.file, final.csv), the
// analysis tables a sweep gathers, the time series that verify and ballagg.load (Python)
// read. Strict, because a field that silently reads as 0 is a wrong result that nobody
// sees: every row must have the header's number of fields, every number must be a number,
// and an error names the file, the line and the column.
//
// The format: fields separated by commas, spaces and tabs around a field ignored, blank
// lines and lines starting with # skipped, the first other line the header. No quoting:
// none of these files has text fields.
//
// Rows are read one at a time, so a state file of 10^8 spheres is never held as fields.
#include <string>
#include <string_view>
#include <vector>

namespace ballagg {

struct CsvRow {
  int line = 0;                         // 1-based line of the file
  std::vector<std::string_view> fields; // views into the text given to the reader
};

class CsvReader {
 public:
  // `text` must outlive the reader. Reads the header; throws InputError for a file without
  // one ("SOURCE: empty file (expected a header line EXPECTED)").
  CsvReader(std::string_view text, std::string source, std::string expected_header);

  const std::string& source() const { return source_; }
  const std::vector<std::string>& columns() const { return columns_; }
  int header_line() const { return header_line_; }
  // The index of a column, or -1.
  int column(std::string_view name) const;

  // The next row into `row`; false at the end. Throws InputError ("SOURCE:LINE: K fields,
  // but the header has M") for a row of another width.
  bool next(CsvRow& row);

  // A field as a number (from_chars: "nan" and "inf" are numbers, the caller judges them);
  // throws InputError "SOURCE:LINE: column NAME: 'FIELD' is not a number".
  double number(const CsvRow& row, int column) const;
  // A field as an integer, with the same kind of error.
  long long integer(const CsvRow& row, int column) const;

 private:
  bool next_line(std::string_view& line);

  std::string_view text_;
  std::size_t position_ = 0;
  int line_no_ = 0;
  std::string source_;
  std::vector<std::string> columns_;
  int header_line_ = 0;
};

}  // namespace ballagg
