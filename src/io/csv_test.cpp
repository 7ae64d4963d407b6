#include "io/csv.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

namespace cmcsurf {
namespace {

// Minimal RFC 4180 reader for checking: rows of fields.
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1);
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') field += text[++i];
      else if (c == '"') quoted = false;
      else field += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().push_back(std::move(field));
      field.clear();
    } else if (c == '\n') {
      rows.back().push_back(std::move(field));
      field.clear();
      rows.emplace_back();
    } else {
      field += c;
    }
  }
  EXPECT_TRUE(rows.back().empty() && field.empty()) << "missing final newline";
  rows.pop_back();
  return rows;
}

TEST(IoCsv, QuotesOnlyWhenNeeded) {
  EXPECT_EQ(csv_quote("plain"), "plain");
  EXPECT_EQ(csv_quote("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_quote("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_quote("two\nlines"), "\"two\nlines\"");
}

TEST(IoCsv, DoublesRoundTripExactly) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> expo(-300, 300);
  std::vector<double> values = {0.1, 1.0 / 3.0, -0.0, 5e-324, std::numeric_limits<double>::max(),
                                std::nextafter(1.0, 2.0)};
  for (int i = 0; i < 200; ++i) values.push_back(std::ldexp(mant(rng), expo(rng)));

  CsvWriter w({"value"});
  for (double v : values) w.add_row(std::vector<double>{v});
  const auto rows = parse_csv(w.str());
  ASSERT_EQ(rows.size(), values.size() + 1);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double back = std::strtod(rows[i + 1][0].c_str(), nullptr);
    EXPECT_EQ(std::memcmp(&back, &values[i], sizeof(double)), 0) << rows[i + 1][0];
  }
}

TEST(IoCsv, MixedRowsSaveAndParseBack) {
  TempDir tmp;
  CsvWriter w({"step", "name, with comma", "energy"});
  w.add_row({0, "P \"primitive\"", 0.25});
  w.add_row({std::size_t{17}, std::string("plain"), 1.0 / 3.0});
  w.add_row({-3, "", std::numeric_limits<double>::quiet_NaN()});
  EXPECT_EQ(w.rows(), 3u);
  const auto path = tmp / "log.csv";
  w.save(path);

  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_EQ(text, w.str());
  const auto rows = parse_csv(text);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"step", "name, with comma", "energy"}));
  EXPECT_EQ(rows[1], (std::vector<std::string>{"0", "P \"primitive\"", "0.25"}));
  EXPECT_EQ(rows[2][0], "17");
  EXPECT_EQ(std::strtod(rows[2][2].c_str(), nullptr), 1.0 / 3.0);
  EXPECT_EQ(rows[3][0], "-3");
  EXPECT_EQ(rows[3][1], "");
  EXPECT_TRUE(std::isnan(std::strtod(rows[3][2].c_str(), nullptr))) << rows[3][2];
}

TEST(IoCsv, RowLengthMustMatchHeader) {
  CsvWriter w({"a", "b"});
  EXPECT_THROW(w.add_row({1.0}), std::invalid_argument);
  EXPECT_THROW(w.add_row(std::vector<double>{1.0, 2.0, 3.0}), std::invalid_argument);
  EXPECT_EQ(w.rows(), 0u);
}

}  // namespace
}  // namespace cmcsurf
