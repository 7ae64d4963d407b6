// Writes the valid seeds of fuzz/corpus/vti/ with the real writer, and the broken ones as
// small edits of them. Not part of any build; from the repository root:
//   g++ -std=c++20 -O1 -fopenmp -Isrc fuzz/make_vti_seeds.cpp src/io/vti.cpp \
//       src/common/atomic_file.cpp src/common/input_file.cpp \
//       src/common/text_encoding.cpp src/grid/field.cpp src/grid/halo.cpp \
//       src/parallel/decomposition.cpp -lfmt -o /tmp/make_vti_seeds && /tmp/make_vti_seeds
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <string>

#include "io/vti.h"

namespace fs = std::filesystem;
using cmcsurf::Field;

namespace {

const fs::path kDir = "fuzz/corpus/vti";

Field gyroid(int n) {
  Field f(n, 1);
  const double tau = 2 * std::numbers::pi;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = tau * (i + 0.5) / n, y = tau * (j + 0.5) / n, z = tau * (k + 0.5) / n;
        f(i, j, k) = 0.5 + 0.3 * (std::sin(x) * std::cos(y) + std::sin(y) * std::cos(z) +
                                  std::sin(z) * std::cos(x));
      }
  f.exchange_halo();
  return f;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put(const std::string& name, const std::string& bytes) {
  std::ofstream(kDir / name, std::ios::binary) << bytes;
}

// `s` with the first `from` replaced by `to` (which must be there).
std::string edit(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  if (at == std::string::npos) throw std::runtime_error("seed edit: no '" + from + "'");
  return s.replace(at, from.size(), to);
}

// The first byte of the appended data: after the '_' marker of <AppendedData encoding="raw">.
std::size_t data_start(const std::string& s) {
  return s.find('_', s.find("encoding=\"raw\"")) + 1;
}

}  // namespace

int main() {
  fs::create_directories(kDir);
  const Field phi4 = gyroid(4), phi8 = gyroid(8);
  Field mu8 = gyroid(8);
  for (std::size_t c = 0; c < mu8.storage_size(); ++c) mu8.data()[c] -= 0.5;
  const std::map<std::string, std::string> meta = {{"surface", "G"}, {"epsilon", "0.01"},
                                                   {"odd key=x", "a--b\n\\"}};
  cmcsurf::write_vti(kDir / "ok-periodic-4-f64.vti", {{"phi", &phi4}}, false, meta);
  cmcsurf::write_vti(kDir / "ok-periodic-8-f32-two-arrays.vti", {{"phi", &phi8}, {"mu", &mu8}},
                     true, meta);
  const std::string w4 = slurp(kDir / "ok-periodic-4-f64.vti");

  // Without the wrap (earlier cmcsurf files, other writers): 4^3 points, UInt32 byte count.
  {
    std::string head = edit(edit(w4, "layout=periodic\n", ""), "header_type=\"UInt64\"",
                            "header_type=\"UInt32\"");
    head = edit(edit(head, "0 4 0 4 0 4", "0 3 0 3 0 3"), "0 4 0 4 0 4", "0 3 0 3 0 3");
    head.resize(data_start(head));
    const std::uint32_t count = 64 * 8;
    head.append(reinterpret_cast<const char*>(&count), 4);
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) head.append(reinterpret_cast<const char*>(&phi4(i, j, k)), 8);
    put("ok-plain-4-uint32.vti", head + "\n  </AppendedData>\n</VTKFile>\n");
  }

  const std::size_t data = data_start(w4);
  put("bad-empty.vti", "");
  put("bad-not-xml.vti", "solid cube\n facet normal 0 0 1\n");
  put("bad-truncated-header.vti", w4.substr(0, data / 2));
  put("bad-truncated-data.vti", w4.substr(0, data + 8 + 100));
  put("bad-no-marker.vti", edit(w4, "   _", "   X"));
  {
    std::string nan = w4;
    const double q = std::nan("");
    std::memcpy(nan.data() + data + 8 + 8 * 7, &q, 8);
    put("bad-nan.vti", nan);
  }
  {
    std::string count = w4;
    count[data] ^= 0x08;
    put("bad-byte-count.vti", count);
  }
  put("bad-n-over-limit.vti", edit(edit(w4, "0 4 0 4 0 4", "0 99 0 99 0 99"), "0 4 0 4 0 4",
                                    "0 99 0 99 0 99"));
  put("bad-not-cubic.vti", edit(w4, "0 4 0 4 0 4", "0 4 0 4 0 5"));
  put("bad-compressed.vti",
      edit(w4, "byte_order", "compressor=\"vtkZLibDataCompressor\" byte_order"));
  put("bad-big-endian.vti", edit(w4, "LittleEndian", "BigEndian"));
  put("bad-int32.vti", edit(w4, "type=\"Float64\" Name=\"phi\"", "type=\"Int32\" Name=\"phi\""));
  put("bad-celldata.vti", edit(edit(w4, "<PointData", "<CellData"),
                               "</PointData>\n      <CellData>", "</CellData>\n      <PointData>"));
  put("bad-unquoted.vti", edit(w4, "offset=\"0\"", "offset=0"));
  put("bad-root.vti", edit(w4, "<VTKFile", "<VTKFilf"));
  {
    const std::string two = edit(
        w4, "</PointData>",
        "  <DataArray type=\"Float64\" Name=\"phi2\" format=\"appended\" offset=\"0\"/>\n"
        "      </PointData>");
    put("bad-overlap.vti", two);
    put("bad-duplicate-name.vti", edit(two, "Name=\"phi2\"", "Name=\"phi\""));
  }
  // An offset that wraps past 2^64 to bytes in the header: a comment holding a byte count and
  // the 5^3 values of a wrapped 4^3 grid, all 0.5, that are not in <AppendedData>.
  {
    std::string hidden(8 + 8 * 125, '\0');
    const std::uint64_t count = 8 * 125;
    const double half = 0.5;
    std::memcpy(hidden.data(), &count, 8);
    for (int c = 0; c < 125; ++c) std::memcpy(hidden.data() + 8 + 8 * c, &half, 8);
    const std::string zeros(20, '0');  // fixed width: the offset does not move the data
    std::string s = edit(w4, "offset=\"0\"", "offset=\"" + zeros + "\"");
    const std::size_t at = s.find('\n') + 1;
    s.insert(at, "<!-- " + hidden + " -->\n");
    const std::size_t hidden_at = at + 5;
    const std::size_t start = data_start(s);
    std::string wrapped = std::to_string(std::uint64_t(0) - start + hidden_at);
    wrapped.insert(0, 20 - wrapped.size(), '0');
    put("bad-offset-wraps.vti", edit(s, zeros, wrapped));
  }
  put("bad-ascii.vti", edit(w4, "format=\"appended\"", "format=\"ascii\""));
  return 0;
}
