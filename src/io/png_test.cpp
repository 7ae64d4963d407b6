#include "io/png.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <utility>

#include "report/report_html.h"
#include "support/temp_dir.h"

namespace cmcsurf {
namespace {

TEST(Png, RoundTripsEveryPixel) {
  Image img(37, 23);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = std::uint8_t(7 * x);
      p[1] = std::uint8_t(11 * y);
      p[2] = std::uint8_t(x * y);
    }
  TempDir tmp("png");
  write_png(tmp / "a.png", img);
  const std::string bytes = encode_png(img);
  ASSERT_GT(bytes.size(), 33u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(bytes.substr(12, 4), "IHDR");
  const Image back = read_png(tmp / "a.png");
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 23);
  EXPECT_EQ(back.rgb, img.rgb);
}

TEST(Png, UnreadableFileNamesItself) {
  TempDir tmp("png");
  {
    std::ofstream(tmp / "bad.png") << "not a png";
  }
  try {
    read_png(tmp / "bad.png");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.png"), std::string::npos) << e.what();
  }
}

TEST(ReportHtml, NumbersCarryAllDigitsAndTheScriptCannotBeClosedByData) {
  const nlohmann::json report = {{"area", 3.0918123456789}, {"grid", 64},
                                 {"surface", "expr:</script><b>"}, {"nodal_area_excess", 0.00123}};
  const std::string table = numbers_table_html(report, run_number_rows(), "numbers");
  const std::string key = "data-key=\"area\" data-value=\"";
  ASSERT_NE(table.find(key), std::string::npos) << table;
  EXPECT_EQ(std::stod(table.substr(table.find(key) + key.size())), 3.0918123456789);
  EXPECT_NE(table.find(">3.091812<"), std::string::npos) << table;
  EXPECT_NE(table.find("data-value=\"64\">64<"), std::string::npos);
  EXPECT_NE(table.find("+0.1230%"), std::string::npos) << table;
  EXPECT_EQ(table.find("<b>"), std::string::npos);
  ReportPage page;
  page.title = "t";
  page.data = {{"surface", "</script><script>alert(1)</script>"}};
  const std::string html = report_page_html(page);
  const std::string open = "id=\"cmc-data\">";
  const auto data = html.find(open);
  ASSERT_NE(data, std::string::npos);
  const auto end = html.find("</script>", data);
  // The element ends where the data ends, and the data reads back unchanged.
  EXPECT_EQ(nlohmann::json::parse(html.substr(data + open.size(), end - data - open.size())),
            page.data);
  EXPECT_EQ(html.find("<script>alert"), std::string::npos);
}

// The zlib encoder against stb's (its twin): both decode to the same pixels, on a picture with
// smooth gradients, flat runs and noise (every Paeth branch and byte wrap-around), and pictures
// one pixel wide.
TEST(Png, EncoderMatchesReferencePixels) {
  TempDir tmp("png");
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{1, 9}, std::pair{301, 77}}) {
    Image img(w, h);
    std::uint32_t state = 12345;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        state = state * 1664525u + 1013904223u;
        std::uint8_t* p = img.pixel(x, y);
        p[0] = std::uint8_t(x < w / 3 ? 2 * x + y : x < 2 * w / 3 ? 200 : state >> 24);
        p[1] = std::uint8_t(255 - 3 * y);
        p[2] = std::uint8_t((x * y) ^ (state >> 16));
      }
    const std::string fast = encode_png(img), ref = encode_png_ref(img);
    {
      std::ofstream(tmp / "fast.png", std::ios::binary) << fast;
      std::ofstream(tmp / "ref.png", std::ios::binary) << ref;
    }
    const Image a = read_png(tmp / "fast.png"), b = read_png(tmp / "ref.png");
    ASSERT_EQ(a.width, w);
    ASSERT_EQ(a.height, h);
    EXPECT_EQ(a.rgb, img.rgb) << w << " x " << h;
    EXPECT_EQ(b.rgb, img.rgb) << w << " x " << h;
  }
}

}  // namespace
}  // namespace cmcsurf
