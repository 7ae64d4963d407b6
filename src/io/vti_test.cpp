#include "io/vti.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/atomic_file.h"
#include "support/file_text.h"
#include "support/temp_dir.h"

namespace cmcsurf {
namespace {

using testing::slurp;

Field random_field(int n, unsigned seed) {
  Field f(n, 1);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> dist(0.0, 1.0);
  for_each_cell(n, [&](int i, int j, int k) { f(i, j, k) = dist(rng); });
  f.exchange_halo();
  return f;
}

bool bit_equal(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

// Value of attribute `name` in the first tag `<tag ...>` of an XML text.
std::string attribute(const std::string& xml, const std::string& tag, const std::string& name) {
  const std::size_t t = xml.find("<" + tag + " ");
  if (t == std::string::npos) return "";
  const std::size_t end = xml.find('>', t);
  const std::size_t a = xml.find(" " + name + "=\"", t);
  if (a == std::string::npos || a > end) return "";
  const std::size_t v = a + name.size() + 3;
  return xml.substr(v, xml.find('"', v) - v);
}

std::vector<double> numbers(const std::string& s) {
  std::istringstream in(s);
  std::vector<double> out;
  for (double v; in >> v;) out.push_back(v);
  return out;
}

// Expects read_vti(path) to throw with every fragment in the message.
void expect_read_error(const std::filesystem::path& path,
                       const std::vector<std::string>& fragments) {
  try {
    read_vti(path);
    ADD_FAILURE() << "read_vti accepted " << path;
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << msg;
  }
}

// A hand-made file in another writer's style: header_type/type/format/etc. as given.
std::string handmade_vti(const std::string& vtkfile_attrs, const std::string& extent,
                         const std::string& array_attrs, const std::string& appended_attrs,
                         const std::string& payload) {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" " + vtkfile_attrs +
         ">\n<ImageData WholeExtent=\"" + extent +
         "\" Origin=\"0 0 0\" Spacing=\"1 1 1\">\n<Piece Extent=\"" + extent +
         "\">\n<PointData Scalars=\"u\">\n<DataArray Name=\"u\" " + array_attrs +
         "/>\n</PointData>\n</Piece>\n</ImageData>\n<AppendedData " + appended_attrs + ">\n_" +
         payload + "\n</AppendedData>\n</VTKFile>\n";
}

TEST(IoVti, Float64RoundTripIsBitIdentical) {
  TempDir tmp;
  const int n = 12;
  const Field phi = random_field(n, 1);
  const auto path = tmp / "phi.vti";
  write_vti(path, {{"phi", &phi}});
  for (int ghost : {0, 1, 2}) {
    const VtiData data = read_vti(path, ghost);
    ASSERT_EQ(data.n, n);
    ASSERT_EQ(data.arrays.size(), 1u);
    const Field& back = data.arrays.at("phi");
    EXPECT_EQ(back.ghost(), ghost);
    int mismatches = 0;
    for_each_cell(
        n, [&](int i, int j, int k) { mismatches += !bit_equal(back(i, j, k), phi(i, j, k)); });
    EXPECT_EQ(mismatches, 0);
    if (ghost > 0) {  // halo filled by the periodic wrap
      EXPECT_TRUE(bit_equal(back(-1, 3, 4), phi(n - 1, 3, 4)));
      EXPECT_TRUE(bit_equal(back(n, n, -1), phi(0, 0, n - 1)));
    }
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(tmp.dir()), {}), 1);
}

TEST(IoVti, Float32RoundTripIsRoundedOnce) {
  TempDir tmp;
  const int n = 9;
  const Field phi = random_field(n, 2);
  const auto path = tmp / "phi32.vti";
  write_vti(path, {{"phi", &phi}}, /*float32=*/true);
  EXPECT_EQ(std::filesystem::file_size(path) > std::uintmax_t(n) * n * n * 4, true);
  EXPECT_LT(std::filesystem::file_size(path), std::uintmax_t(n) * n * n * 8);
  const VtiData data = read_vti(path);
  const Field& back = data.arrays.at("phi");
  // Round to nearest float: relative error at most eps_float / 2.
  const double tol = std::numeric_limits<float>::epsilon() / 2;
  double worst = 0;
  for_each_cell(n, [&](int i, int j, int k) {
    EXPECT_EQ(back(i, j, k), static_cast<double>(static_cast<float>(phi(i, j, k))));
    worst = std::max(worst, std::abs(back(i, j, k) - phi(i, j, k)) / std::abs(phi(i, j, k)));
  });
  EXPECT_LE(worst, tol);
}

TEST(IoVti, TwoArraysKeepNamesAndOrder) {
  TempDir tmp;
  const int n = 8;
  const Field phi = random_field(n, 3), mu = random_field(n, 4);
  const auto path = tmp / "two.vti";
  write_vti(path, {{"phi", &phi}, {"mu", &mu}});
  const std::string text = slurp(path);
  EXPECT_EQ(attribute(text, "PointData", "Scalars"), "phi");
  EXPECT_LT(text.find("Name=\"phi\""), text.find("Name=\"mu\""));
  EXPECT_NE(text.find("offset=\"" + std::to_string(8 + 8 * (n + 1) * (n + 1) * (n + 1)) + "\""),
            std::string::npos);

  const VtiData data = read_vti(path);
  ASSERT_EQ(data.arrays.size(), 2u);
  int mismatches = 0;
  for_each_cell(n, [&](int i, int j, int k) {
    mismatches += !bit_equal(data.arrays.at("phi")(i, j, k), phi(i, j, k));
    mismatches += !bit_equal(data.arrays.at("mu")(i, j, k), mu(i, j, k));
  });
  EXPECT_EQ(mismatches, 0);
}

TEST(IoVti, HeaderDescribesCellCentres) {
  TempDir tmp;
  const int n = 10;
  Field phi(n, 1);
  for_each_cell(n, [&](int i, int j, int k) { phi(i, j, k) = i + 100 * j + 10000 * k; });
  const auto path = tmp / "h.vti";
  write_vti(path, {{"phi", &phi}});
  const std::string text = slurp(path);
  EXPECT_TRUE(text.starts_with("<?xml version=\"1.0\"?>\n<!-- cmcsurf"));
  EXPECT_EQ(attribute(text, "VTKFile", "type"), "ImageData");
  EXPECT_EQ(attribute(text, "VTKFile", "byte_order"), "LittleEndian");
  EXPECT_EQ(attribute(text, "VTKFile", "header_type"), "UInt64");
  // N + 1 points per axis: the cell centres and the periodic wrap.
  EXPECT_EQ(attribute(text, "ImageData", "WholeExtent"), "0 10 0 10 0 10");
  EXPECT_EQ(attribute(text, "Piece", "Extent"), "0 10 0 10 0 10");
  EXPECT_NE(text.find("\nlayout=periodic\n"), std::string::npos);
  EXPECT_EQ(numbers(attribute(text, "ImageData", "Spacing")), std::vector<double>(3, 0.1));
  EXPECT_EQ(numbers(attribute(text, "ImageData", "Origin")), std::vector<double>(3, 0.05));
  EXPECT_EQ(attribute(text, "DataArray", "type"), "Float64");
  EXPECT_EQ(attribute(text, "DataArray", "format"), "appended");
  EXPECT_EQ(attribute(text, "AppendedData", "encoding"), "raw");

  // Raw block: UInt64 byte count, then values with x fastest, then y, then z; point n on
  // each axis repeats point 0.
  const std::size_t data = text.find('_', text.find("<AppendedData")) + 1;
  std::uint64_t count = 0;
  std::memcpy(&count, text.data() + data, 8);
  const std::size_t m = n + 1;
  EXPECT_EQ(count, 8u * m * m * m);
  auto value = [&](std::size_t idx) {
    double v;
    std::memcpy(&v, text.data() + data + 8 + 8 * idx, 8);
    return v;
  };
  EXPECT_EQ(value(1), 1.0);
  EXPECT_EQ(value(n), 0.0);  // x wrap of point 0
  EXPECT_EQ(value(m), 100.0);
  EXPECT_EQ(value(m * m), 10000.0);
  EXPECT_EQ(value(m * m * n + m * 3 + 2), 2.0 + 300.0);  // z wrap of cell (2, 3, 0)
  EXPECT_TRUE(text.ends_with("\n  </AppendedData>\n</VTKFile>\n"));
}

TEST(IoVti, MetadataInCommentAndFieldData) {
  TempDir tmp;
  const Field phi = random_field(4, 5);
  const std::map<std::string, std::string> meta = {
      {"surface", "P"},
      {"epsilon", "0.0123"},
      {"volume_fraction", "0.5"},
      {"command", "cmcsurf run --surface P -- x  <a> & \"b\""},
      {"odd=key", "line1\nline2\\-\t-"},
      {"nan", "nan"},
  };
  const auto path = tmp / "m.vti";
  write_vti(path, {{"phi", &phi}}, false, meta);
  const std::string text = slurp(path);
  const std::size_t open = text.find("<!--") + 4;
  const std::string comment = text.substr(open, text.find("-->") - open);
  EXPECT_NE(comment.find("\nsurface=P\n"), std::string::npos) << comment;
  EXPECT_NE(comment.find("\nepsilon=0.0123\n"), std::string::npos) << comment;
  EXPECT_EQ(comment.find("--"), std::string::npos) << "'--' is not allowed inside an XML comment";
  EXPECT_NE(text.find("<DataArray type=\"Float64\" Name=\"epsilon\" NumberOfTuples=\"1\" "
                      "format=\"ascii\">0.0123</DataArray>"),
            std::string::npos);
  EXPECT_NE(text.find("Name=\"volume_fraction\""), std::string::npos);
  EXPECT_EQ(text.find("Name=\"surface\""), std::string::npos);  // not numeric: comment only
  EXPECT_EQ(text.find("Name=\"nan\""), std::string::npos);      // not finite: comment only
  auto with_layout = meta;
  with_layout["layout"] = "periodic";
  EXPECT_EQ(read_vti(path).metadata, with_layout);
}

TEST(IoVti, RejectsTruncatedFile) {
  TempDir tmp;
  const Field phi = random_field(6, 6);
  const auto path = tmp / "t.vti";
  write_vti(path, {{"phi", &phi}});
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 100);
  expect_read_error(path, {"truncated", "'phi'"});

  std::filesystem::resize_file(path, 300);  // ends inside the XML header
  expect_read_error(path, {"truncated"});
}

TEST(IoVti, RejectsNonCubicExtent) {
  TempDir tmp;
  const Field phi = random_field(8, 7);
  const auto path = tmp / "e.vti";
  write_vti(path, {{"phi", &phi}});
  std::string text = slurp(path);
  const std::size_t at = text.find("WholeExtent=\"0 8 0 8 0 8\"");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 25, "WholeExtent=\"0 8 0 8 0 3\"");
  write_file_atomic(path, text);
  expect_read_error(path, {"WholeExtent=\"0 8 0 8 0 3\"", "0 N-1 0 N-1 0 N-1"});
}

TEST(IoVti, RejectsOtherEncodings) {
  TempDir tmp;
  const auto path = tmp / "other.vti";
  const std::string le = "byte_order=\"LittleEndian\" header_type=\"UInt64\"";
  const std::string f64 = "type=\"Float64\" format=\"appended\" offset=\"0\"";

  write_file_atomic(path, handmade_vti(le + " compressor=\"vtkZLibDataCompressor\"", "0 1 0 1 0 1",
                                       f64, "encoding=\"raw\"", ""));
  expect_read_error(path, {"compressor=\"vtkZLibDataCompressor\"", "uncompressed"});

  write_file_atomic(path, handmade_vti(le, "0 1 0 1 0 1", "type=\"Float64\" format=\"ascii\"",
                                       "encoding=\"raw\"", ""));
  expect_read_error(path, {"format=\"ascii\"", "format=\"appended\""});

  write_file_atomic(path, handmade_vti(le, "0 1 0 1 0 1", "type=\"Float64\" format=\"binary\"",
                                       "encoding=\"raw\"", ""));
  expect_read_error(path, {"format=\"binary\""});

  write_file_atomic(path, handmade_vti(le, "0 1 0 1 0 1", f64, "encoding=\"base64\"", "AAAA"));
  expect_read_error(path, {"encoding=\"base64\"", "encoding=\"raw\""});

  write_file_atomic(path, handmade_vti("byte_order=\"BigEndian\"", "0 1 0 1 0 1", f64,
                                       "encoding=\"raw\"", ""));
  expect_read_error(path, {"BigEndian"});

  write_file_atomic(
      path, handmade_vti(le, "0 1 0 1 0 1", "type=\"Int32\" format=\"appended\" offset=\"0\"",
                         "encoding=\"raw\"", ""));
  expect_read_error(path, {"type=\"Int32\"", "Float32 or Float64"});

  write_file_atomic(path, "<?xml version=\"1.0\"?>\n<VTKFile type=\"RectilinearGrid\">\n");
  expect_read_error(path, {"type=\"RectilinearGrid\"", "ImageData"});

  expect_read_error(tmp / "missing.vti", {"No such file"});
}

TEST(IoVti, WrongByteCountIsReported) {
  TempDir tmp;
  const auto path = tmp / "count.vti";
  std::string payload(8 + 8 * 8, '\0');
  const std::uint64_t wrong = 7 * 8;
  std::memcpy(payload.data(), &wrong, 8);
  write_file_atomic(
      path, handmade_vti("byte_order=\"LittleEndian\" header_type=\"UInt64\"", "0 1 0 1 0 1",
                         "type=\"Float64\" format=\"appended\" offset=\"0\"", "encoding=\"raw\"",
                         payload));
  expect_read_error(path, {"byte count of 56", "64 bytes"});
}

TEST(IoVti, ReadsUInt32HeaderAndFloat32FromOtherWriters) {
  TempDir tmp;
  const int n = 3;
  std::vector<float> values(n * n * n);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.25f * float(i) - 1.0f;
  std::string payload(4 + 4 * values.size(), '\0');
  const std::uint32_t count = 4 * values.size();
  std::memcpy(payload.data(), &count, 4);
  std::memcpy(payload.data() + 4, values.data(), 4 * values.size());
  const auto path = tmp / "u32.vti";
  // No header_type: VTK's default is UInt32.
  write_file_atomic(path, handmade_vti("byte_order=\"LittleEndian\"", "0 2 0 2 0 2",
                                       "type=\"Float32\" format=\"appended\" offset=\"0\"",
                                       "encoding=\"raw\"", payload));
  const VtiData data = read_vti(path, 1);
  ASSERT_EQ(data.n, n);
  const Field& u = data.arrays.at("u");
  for_each_cell(n, [&](int i, int j, int k) {
    EXPECT_EQ(u(i, j, k), double(values[i + n * (j + n * k)]));
  });
  EXPECT_EQ(u(-1, 0, 0), u(n - 1, 0, 0));
  EXPECT_TRUE(data.metadata.empty());
}

TEST(IoVti, WriterRejectsBadArguments) {
  TempDir tmp;
  const Field a(4, 1), b(5, 1);
  EXPECT_THROW(write_vti(tmp / "x.vti", {}), std::invalid_argument);
  EXPECT_THROW(write_vti(tmp / "x.vti", {{"a", &a}, {"b", &b}}), std::invalid_argument);
  EXPECT_THROW(write_vti(tmp / "x.vti", {{"a", &a}, {"a", &a}}), std::invalid_argument);
  EXPECT_THROW(write_vti(tmp / "x.vti", {{"a", nullptr}}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(tmp / "x.vti"));
}

}  // namespace
}  // namespace cmcsurf

namespace cmcsurf {
namespace {

// Hostile and damaged inputs: refused with the file and the problem named, before
// anything large is allocated.
TEST(IoVtiBadData, NonFiniteValuesAreRefused) {
  TempDir tmp;
  Field phi = random_field(8, 11);
  phi(3, 4, 5) = std::nan("");
  const auto path = tmp / "nan.vti";
  write_vti(path, {{"phi", &phi}});
  expect_read_error(path, {"'phi'", "non-finite", "(3, 4, 5)"});
  phi(3, 4, 5) = INFINITY;
  write_vti(path, {{"phi", &phi}}, true);
  expect_read_error(path, {"non-finite", "inf"});
}

TEST(IoVtiBadData, ArraysSharingBytesAreRefused) {
  // K arrays named at one offset would each be allocated from the same N^3 bytes.
  TempDir tmp;
  const int n = 8;
  const Field phi = random_field(n, 3), mu = random_field(n, 4);
  const auto path = tmp / "overlap.vti";
  write_vti(path, {{"phi", &phi}, {"mu", &mu}});
  std::string text = slurp(path);
  const std::string second =
      "offset=\"" + std::to_string(8 + 8 * (n + 1) * (n + 1) * (n + 1)) + "\"";
  const std::size_t at = text.find(second);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, second.size(), "offset=\"0\"" + std::string(second.size() - 10, ' '));
  write_file_atomic(path, text);
  expect_read_error(path, {"overlap", "'phi'", "'mu'"});
}

TEST(IoVtiBadData, HeaderWithoutMarkerIsNotReadToTheEnd) {
  TempDir tmp;
  const auto path = tmp / "nomarker.vti";
  std::string text = "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" "
                     "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<!-- ";
  text += std::string(2 * kMaxVtiHeaderBytes, 'x');
  text += " -->\n</VTKFile>\n";
  write_file_atomic(path, text);
  expect_read_error(path, {"first 1048576 bytes"});
}

TEST(IoVtiBadData, SizeLimitAndOneArrayAreCheckedBeforeReading) {
  TempDir tmp;
  const Field phi = random_field(16, 5), mu = random_field(16, 6);
  const auto path = tmp / "two.vti";
  write_vti(path, {{"mu", &mu}, {"phi", &phi}});
  VtiReadOptions small;
  small.max_n = 8;
  try {
    read_vti(path, small);
    ADD_FAILURE() << "accepted N = 16 over a limit of 8";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("N = 16 exceeds the limit 8"), std::string::npos)
        << e.what();
  }
  VtiReadOptions only_phi;
  only_phi.only = "phi";
  const VtiData d = read_vti(path, only_phi);
  ASSERT_EQ(d.arrays.size(), 1u);
  EXPECT_EQ(d.arrays.at("phi")(1, 2, 3), phi(1, 2, 3));
  VtiReadOptions missing;
  missing.only = "nu";
  try {
    read_vti(path, missing);
    ADD_FAILURE() << "accepted a missing array";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no array 'nu' (found 'mu', 'phi')"), std::string::npos)
        << e.what();
  }
}

TEST(IoVtiBadData, OffsetWrappingPastTheEndIsRefused) {
  // data_start + offset wrapped modulo 2^64 to bytes of the header (found while writing the
  // fuzz corpus, fuzz/corpus/vti/bad-offset-wraps.vti): a comment hiding a valid byte count
  // and values was read as phi.
  TempDir tmp;
  const int n = 4, m = n + 1;
  const Field phi = random_field(n, 7);
  const auto path = tmp / "wrap.vti";
  write_vti(path, {{"phi", &phi}});
  std::string text = slurp(path);
  std::string hidden(8 + 8 * m * m * m, '\0');
  const std::uint64_t count = 8 * m * m * m;
  const double half = 0.5;
  std::memcpy(hidden.data(), &count, 8);
  for (int c = 0; c < m * m * m; ++c) std::memcpy(hidden.data() + 8 + 8 * c, &half, 8);
  text.insert(text.find('\n') + 1, "<!-- " + hidden + " -->\n");
  const std::size_t hidden_at = text.find("<!-- ") + 5;
  const std::string zeros = "offset=\"00000000000000000000\"";  // fixed width
  text.replace(text.find("offset=\"0\""), 10, zeros);
  const std::size_t data = text.find('_', text.find("encoding=\"raw\"")) + 1;
  const std::string wrapped = std::to_string(std::uint64_t(0) - data + hidden_at);
  text.replace(text.find(zeros) + 8, 20, std::string(20 - wrapped.size(), '0') + wrapped);
  write_file_atomic(path, text);
  expect_read_error(path, {"'phi'", "offset " + wrapped, "beyond the end of the file"});
}

TEST(IoVtiBadData, UnknownLayoutIsRefused) {
  // layout= is cmcsurf's own key: an unknown value must not be read as "no wrap".
  TempDir tmp;
  const Field phi = random_field(4, 12);
  const auto path = tmp / "layout.vti";
  write_vti(path, {{"phi", &phi}});
  std::string text = slurp(path);
  const std::string ours = "layout=periodic\n";
  ASSERT_NE(text.find(ours), std::string::npos);
  write_file_atomic(path, text.replace(text.find(ours), ours.size(), "layout=tiled\n"));
  expect_read_error(path, {"layout=tiled", "layout=periodic"});
}

TEST(IoVtiBadData, DataShortOfItsClosingTagsIsRefused) {
  // 8 bytes missing from the appended data: the closing tags would be read as the last value.
  TempDir tmp;
  const Field phi = random_field(4, 13);
  const auto path = tmp / "short.vti";
  write_vti(path, {{"phi", &phi}});
  std::string text = slurp(path);
  const std::size_t tail = text.rfind("\n  </AppendedData>");
  ASSERT_NE(tail, std::string::npos);
  write_file_atomic(path, text.erase(tail - 8, 8));
  expect_read_error(path, {"'phi'", "</AppendedData>"});
  // Trailing bytes after the closing tags are refused too; the exact file reads.
  write_vti(path, {{"phi", &phi}});
  EXPECT_NO_THROW(read_vti(path));
  write_file_atomic(path, slurp(path) + "junk");
  expect_read_error(path, {"</VTKFile>"});
}

TEST(IoVti, ParseFromMemoryIsTheFileReader) {
  TempDir tmp;
  const Field phi = random_field(6, 8), mu = random_field(6, 9);
  const auto path = tmp / "two.vti";
  write_vti(path, {{"phi", &phi}, {"mu", &mu}}, false, {{"surface", "G"}});
  const std::string text = slurp(path);
  const auto* first = reinterpret_cast<const unsigned char*>(text.data());
  const VtiData from_file = read_vti(path);
  const VtiData from_memory = parse_vti({first, text.size()});
  ASSERT_EQ(from_memory.n, from_file.n);
  ASSERT_EQ(from_memory.arrays.size(), 2u);
  EXPECT_EQ(from_memory.metadata, from_file.metadata);
  for (const auto& [name, f] : from_file.arrays) {
    const Field& g = from_memory.arrays.at(name);
    for (int k = -1; k <= 6; ++k)
      for (int j = -1; j <= 6; ++j)
        for (int i = -1; i <= 6; ++i) ASSERT_TRUE(bit_equal(f(i, j, k), g(i, j, k))) << name;
  }
  // The source's name stands for the path in messages.
  try {
    parse_vti({first, text.size() - 100}, {}, "bytes of two.vti");
    ADD_FAILURE() << "accepted a truncated copy";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot read VTI file 'bytes of two.vti': file truncated"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace cmcsurf
