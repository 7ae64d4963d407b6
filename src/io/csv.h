// Small CSV tables (RFC 4180 quoting), built in memory and saved atomically.
#pragma once

#include <concepts>
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cmcsurf {

// One cell, formatted on construction: doubles with "{:.17g}" (round-trips
// exactly; non-finite values print as nan, inf, -inf), integers exactly,
// strings verbatim (quoted on output when they contain , " CR or LF).
class CsvCell {
 public:
  CsvCell(double value);
  template <std::integral I>
  CsvCell(I value) : CsvCell(static_cast<long long>(value), IntegerTag{}) {}
  CsvCell(std::string value) : text_(std::move(value)), is_string_(true) {}
  CsvCell(std::string_view value) : CsvCell(std::string(value)) {}
  CsvCell(const char* value) : CsvCell(std::string(value)) {}

  const std::string& text() const { return text_; }
  bool is_string() const { return is_string_; }

 private:
  struct IntegerTag {};
  CsvCell(long long value, IntegerTag);
  std::string text_;
  bool is_string_ = false;
};

class CsvWriter {
 public:
  explicit CsvWriter(std::vector<std::string> header);

  // Each row must have as many cells as the header (else std::invalid_argument).
  void add_row(const std::vector<CsvCell>& row);
  void add_row(std::span<const double> row);

  std::size_t columns() const { return header_.size(); }
  std::size_t rows() const { return rows_.size(); }
  std::string str() const;  // header line then rows, each ending in '\n'
  void save(const std::filesystem::path& path) const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<CsvCell>> rows_;
};

// The field as written in a CSV line: quoted with doubled quotes if needed.
std::string csv_quote(std::string_view text);

}  // namespace cmcsurf
