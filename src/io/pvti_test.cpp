#include "io/pvti.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../tests/test_fields.h"
#include "support/file_text.h"
#include "support/temp_dir.h"

// One process: a whole field is one piece (tests/mpi/pvti_test.cpp writes several, under
// mpirun). The hostile files are the one-piece layout edited, or written by hand.
namespace cmcsurf {
namespace {

using testing::slurp;
using testing::spit;

bool bit_equal_interiors(const Field& a, const Field& b) {
  if (a.n() != b.n() || a.size() != b.size()) return false;
  bool same = true;
  for_each_cell(a, [&](int i, int j, int k) {
    same = same && std::memcmp(&a(i, j, k), &b(i, j, k), sizeof(double)) == 0;
  });
  return same;
}

// read_pvti's message for the file, "" if it reads.
std::string pvti_error(const std::filesystem::path& p, const VtiReadOptions& o = {}) {
  try {
    read_pvti(p, o);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// A .pvti text with the given pieces, N = 8, layout=periodic unless `comment` is empty.
std::string pvti_text(const std::string& pieces, const std::string& type = "Float64",
                      const std::string& comment = "<!-- cmcsurf\nlayout=periodic\n-->\n",
                      const std::string& extra_data = "") {
  return "<?xml version=\"1.0\"?>\n" + comment +
         "<VTKFile type=\"PImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
         "<PImageData WholeExtent=\"0 8 0 8 0 8\" GhostLevel=\"0\" Origin=\"0 0 0\" "
         "Spacing=\"1 1 1\">\n<PPointData Scalars=\"phi\">\n<PDataArray type=\"" +
         type + "\" Name=\"phi\"/>\n</PPointData>\n" + extra_data + pieces +
         "</PImageData>\n</VTKFile>\n";
}

const char* kWholePiece = "<Piece Extent=\"0 8 0 8 0 8\" Source=\"field/piece_0000.vti\"/>\n";

TEST(IoPvti, OnePieceEqualsTheSerialFileBitForBit) {
  TempDir tmp("cmcsurf-pvti");
  const Field phi = testing::random_field(8, 2, -1, 1, 5);
  const Field nu = testing::random_field(8, 1, -3, 3, 6);
  const std::map<std::string, std::string> meta = {{"surface", "G"}, {"area", "2.5"}};
  for (const bool float32 : {false, true}) {
    write_pvti(tmp / "field.pvti", {{"phi", &phi}, {"nu", &nu}}, float32, meta);
    write_vti(tmp / "serial.vti", {{"phi", &phi}, {"nu", &nu}}, float32, meta);
    // One piece holds the whole grid: the piece file is field.vti itself.
    EXPECT_EQ(slurp(tmp / "field" / "piece_0000.vti"), slurp(tmp / "serial.vti"));
    const std::string summary = slurp(tmp / "field.pvti");
    EXPECT_NE(summary.find("<PImageData WholeExtent=\"0 8 0 8 0 8\" GhostLevel=\"0\" "
                           "Origin=\"0.0625 0.0625 0.0625\" Spacing=\"0.125 0.125 0.125\">"),
              std::string::npos)
        << summary;
    EXPECT_NE(summary.find(std::string("<PDataArray type=\"") + (float32 ? "Float32" : "Float64") +
                           "\" Name=\"nu\"/>"),
              std::string::npos);
    EXPECT_NE(summary.find(kWholePiece), std::string::npos) << summary;
    const VtiData a = read_pvti(tmp / "field.pvti");
    const VtiData b = read_vti(tmp / "serial.vti");
    EXPECT_EQ(a.n, 8);
    EXPECT_EQ(a.metadata, b.metadata);
    for (const char* name : {"phi", "nu"}) {
      EXPECT_TRUE(bit_equal_interiors(a.arrays.at(name), b.arrays.at(name))) << name;
      EXPECT_TRUE(halo_is_current(a.arrays.at(name)));
    }
    if (!float32) {
      EXPECT_TRUE(bit_equal_interiors(a.arrays.at("phi"), phi));
    }
    // read_field_file picks the reader by the extension; run_field_file finds the one file.
    EXPECT_TRUE(bit_equal_interiors(read_field_file(tmp / "field.pvti").arrays.at("nu"),
                                    b.arrays.at("nu")));
  }
  Field block(8, 1);
  read_pvti_block_interior_only(tmp / "field.pvti", "phi", block);
  EXPECT_TRUE(bit_equal_interiors(block, read_vti(tmp / "serial.vti").arrays.at("phi")));
}

TEST(IoPvti, RunFolderHoldsOneFieldFile) {
  TempDir tmp("cmcsurf-pvti");
  const Field phi = testing::random_field(8, 2, 0, 1, 7);
  EXPECT_THROW(run_field_file(tmp.dir()), std::runtime_error);  // neither
  EXPECT_EQ(write_run_field(tmp.dir(), {{"phi", &phi}}, false, {}), tmp / kRunFieldVti);
  EXPECT_EQ(run_field_file(tmp.dir()), tmp / kRunFieldVti);
  write_pvti(tmp / kRunFieldPvti, {{"phi", &phi}});
  try {
    run_field_file(tmp.dir());
    ADD_FAILURE() << "both files accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("holds both field.vti and field.pvti"), std::string::npos);
  }
  // Stale pieces of an earlier, larger write go with their summary; other files stay.
  spit(tmp / "field" / "piece_0007.vti", "stale");
  spit(tmp / "field" / "piece_0001.vti.cmcsurf-tmp.99999999.0", "killed writer");
  spit(tmp / "field" / "notes.txt", "mine");
  remove_run_field(tmp.dir());
  EXPECT_FALSE(std::filesystem::exists(tmp / kRunFieldVti));
  EXPECT_FALSE(std::filesystem::exists(tmp / kRunFieldPvti));
  EXPECT_FALSE(std::filesystem::exists(tmp / "field" / "piece_0000.vti"));
  EXPECT_FALSE(std::filesystem::exists(tmp / "field" / "piece_0007.vti"));
  EXPECT_FALSE(std::filesystem::exists(tmp / "field" / "piece_0001.vti.cmcsurf-tmp.99999999.0"));
  EXPECT_TRUE(std::filesystem::exists(tmp / "field" / "notes.txt"));
  std::filesystem::remove(tmp / "field" / "notes.txt");
  write_pvti(tmp / kRunFieldPvti, {{"phi", &phi}});
  remove_run_field(tmp.dir());
  EXPECT_FALSE(std::filesystem::exists(tmp / "field"));  // emptied, so removed
  remove_run_field(tmp.dir());                          // nothing there: fine
}

// Hostile .pvti files around one real piece: each refused, naming the file and the problem.
TEST(IoPvti, RefusesHostileSummariesNamingTheProblem) {
  TempDir tmp("cmcsurf-pvti");
  const Field phi = testing::random_field(8, 2, 0, 1, 8);
  write_pvti(tmp / "field.pvti", {{"phi", &phi}});
  ASSERT_EQ(pvti_error(tmp / "field.pvti"), "");
  auto refused = [&](const std::string& text, const std::string& fragment,
                     const VtiReadOptions& o = {}) {
    spit(tmp / "h.pvti", text);
    const std::string why = pvti_error(tmp / "h.pvti", o);
    EXPECT_NE(why.find("h.pvti"), std::string::npos) << why;
    EXPECT_NE(why.find(fragment), std::string::npos) << "want '" << fragment << "' in: " << why;
  };
  spit(tmp / "h.pvti", pvti_text(kWholePiece));  // a hand-written copy reads
  EXPECT_EQ(pvti_error(tmp / "h.pvti"), "");
  // Tiling: a gap, an overlap, a piece outside, an empty piece.
  refused(pvti_text("<Piece Extent=\"0 8 0 8 0 4\" Source=\"field/piece_0000.vti\"/>\n"),
          "the pieces hold 256 of the grid's 512 cells");
  refused(pvti_text(std::string(kWholePiece) + kWholePiece),
          "piece 1 ('field/piece_0000.vti') holds cell (0, 0, 0), which an earlier piece");
  refused(pvti_text("<Piece Extent=\"0 9 0 8 0 8\" Source=\"field/piece_0000.vti\"/>\n"),
          "inside the WholeExtent");
  refused(pvti_text("<Piece Extent=\"0 8 0 8 3 3\" Source=\"field/piece_0000.vti\"/>\n" +
                    std::string(kWholePiece)),
          "at least one cell");
  refused(pvti_text(""), "no <Piece> found");
  // Pieces: missing, outside the folder, another extent, another type.
  refused(pvti_text("<Piece Extent=\"0 8 0 8 0 8\" Source=\"field/piece_0001.vti\"/>\n"),
          "piece 0 'field/piece_0001.vti' is missing");
  refused(pvti_text("<Piece Extent=\"0 8 0 8 0 8\" Source=\"../field/piece_0000.vti\"/>\n"),
          "a relative path without '..'");
  refused(pvti_text("<Piece Extent=\"0 8 0 8 0 8\" Source=\"/etc/passwd\"/>\n"),
          "a relative path without '..'");
  refused(pvti_text("<Piece Extent=\"0 8 0 8 0 8\"/>\n"), "has no Source");
  refused(pvti_text("<Piece Source=\"field/piece_0000.vti\"/>\n"), "has no Extent");
  refused(pvti_text("<Piece Extent=\"0 8 0 8 x 8\" Source=\"field/piece_0000.vti\"/>\n"),
          "malformed Extent");
  refused(pvti_text(kWholePiece, "Float32"), "array 'phi' is Float64, but");
  // Structure: root, layout, cell data, ghost levels, limits, truncation.
  refused(pvti_text(kWholePiece, "Int32"), "only Float32 or Float64");
  refused(pvti_text(kWholePiece, "Float64", ""), "only cmcsurf's periodic layout");
  refused(pvti_text(kWholePiece, "Float64", "<!-- cmcsurf\nlayout=periodic\n-->\n",
                    "<PCellData><PDataArray type=\"Float64\" Name=\"c\"/></PCellData>\n"),
          "PCellData array 'c' is not supported");
  std::string text = pvti_text(kWholePiece);
  refused(text.substr(0, text.size() / 2), "file truncated");
  refused(std::string(text).replace(text.find("GhostLevel=\"0\""), 14, "GhostLevel=\"1\""),
          "GhostLevel=\"1\" is not supported");
  refused(std::string(text).replace(text.find("type=\"PImageData\""), 17, "type=\"ImageData\""),
          "only type=\"PImageData\"");
  refused(std::string(text).replace(text.find("0 8 0 8 0 8\" Ghost"), 11, "0 8 0 8 0 9"),
          "only a cubic extent");
  VtiReadOptions small;
  small.max_n = 4;
  refused(text, "N = 8 exceeds the limit 4", small);
  small.max_n = 8;
  small.only = "mu";
  refused(text, "no array 'mu' (found 'phi')", small);
  // A damaged piece is named as the piece.
  std::string piece = slurp(tmp / "field" / "piece_0000.vti");
  spit(tmp / "field" / "piece_0000.vti", piece.substr(0, piece.size() - 100));
  const std::string why = pvti_error(tmp / "field.pvti");
  EXPECT_NE(why.find("piece_0000.vti"), std::string::npos) << why;
  EXPECT_NE(why.find("truncated"), std::string::npos) << why;
}

TEST(IoPvti, PieceSizesAndLayoutAreCheckedBeforeAllocating) {
  TempDir tmp;
  const Field phi = testing::random_field(8, 2, 0, 1, 8);
  write_pvti(tmp / "field.pvti", {{"phi", &phi}});
  // A piece file too small for its Extent is refused from its size, before the grid is
  // allocated or the piece read (a 1 kB summary could otherwise claim N = 8192).
  const std::string piece = slurp(tmp / "field" / "piece_0000.vti");
  spit(tmp / "field" / "piece_0000.vti", piece.substr(0, 1000));
  std::string why = pvti_error(tmp / "field.pvti");
  EXPECT_NE(why.find("field.pvti"), std::string::npos) << why;
  EXPECT_NE(why.find("piece 0 ('field/piece_0000.vti') has 1000 bytes"), std::string::npos)
      << why;
  spit(tmp / "field" / "piece_0000.vti", piece);
  EXPECT_EQ(pvti_error(tmp / "field.pvti"), "");
  // An unknown layout is named.
  spit(tmp / "h.pvti", pvti_text(kWholePiece, "Float64", "<!-- cmcsurf\nlayout=tiled\n-->\n"));
  why = pvti_error(tmp / "h.pvti");
  EXPECT_NE(why.find("layout=tiled"), std::string::npos) << why;
}

}  // namespace
}  // namespace cmcsurf
