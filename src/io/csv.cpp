#include "io/csv.h"

#include <stdexcept>

#include <fmt/core.h>

#include "common/atomic_file.h"

namespace cmcsurf {

CsvCell::CsvCell(double value) : text_(fmt::format("{:.17g}", value)) {}

CsvCell::CsvCell(long long value, IntegerTag) : text_(fmt::format("{}", value)) {}

std::string csv_quote(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
  return out;
}

CsvWriter::CsvWriter(std::vector<std::string> header) : header_(std::move(header)) {
  if (header_.empty()) throw std::invalid_argument("CsvWriter: empty header");
}

void CsvWriter::add_row(const std::vector<CsvCell>& row) {
  if (row.size() != header_.size())
    throw std::invalid_argument(
        fmt::format("CsvWriter: row {} has {} cells, the header has {} columns", rows_.size() + 1,
                    row.size(), header_.size()));
  rows_.push_back(row);
}

void CsvWriter::add_row(std::span<const double> row) {
  add_row(std::vector<CsvCell>(row.begin(), row.end()));
}

std::string CsvWriter::str() const {
  std::string out;
  auto append_line = [&out](const auto& cells, auto&& text_of) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (i) out += ',';
      out += text_of(cells[i]);
    }
    out += '\n';
  };
  append_line(header_, [](const std::string& s) { return csv_quote(s); });
  for (const auto& row : rows_)
    append_line(row,
                [](const CsvCell& c) { return c.is_string() ? csv_quote(c.text()) : c.text(); });
  return out;
}

void CsvWriter::save(const std::filesystem::path& path) const { write_file_atomic(path, str()); }

}  // namespace cmcsurf
