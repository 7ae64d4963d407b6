// Writes the valid seeds of fuzz/corpus/checkpoint/ with the real writer, and the broken ones
// as small edits of them. Not part of any build; from the repository root:
//   g++ -std=c++20 -O1 -fopenmp -Isrc -DCMCSURF_VERSION='"0.1.0"' fuzz/make_checkpoint_seeds.cpp \
//       src/io/checkpoint.cpp src/io/atomic_file.cpp src/grid/field.cpp src/grid/halo.cpp \
//       src/parallel/decomposition.cpp -lfmt -lz -o /tmp/make_checkpoint_seeds \
//     && /tmp/make_checkpoint_seeds
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <zlib.h>

#include "io/checkpoint.h"

namespace fs = std::filesystem;
using cmcsurf::Field;

namespace {

const fs::path kDir = "fuzz/corpus/checkpoint";

Field smooth(int n, int ghost, double shift) {
  Field f(n, ghost);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        f(i, j, k) = shift + 0.25 * std::sin(6.283185307179586 * (i + 2 * j + 3 * k) / n);
  f.exchange_halo();
  return f;
}

cmcsurf::Checkpoint state(int n, bool stepper_fields) {
  cmcsurf::Checkpoint c;
  c.cursor.grid = n;
  c.cursor.stage = stepper_fields ? "volume" : "relax";
  c.cursor.stage_steps = 2;
  c.cursor.dt = 0.5 / n;
  c.cursor.area = 2.3;
  c.cursor.volume = 0.31;
  c.step = 2;
  c.time = 1.0 / n;
  c.result.phi = smooth(n, 2, 0.5);
  for (int s = 1; s <= 2; ++s) {
    cmcsurf::StepRecord r;
    r.step = s;
    r.stage = c.cursor.stage;
    r.time = s * c.cursor.dt;
    r.dt = c.cursor.dt;
    r.area = 2.3;
    c.result.history.push_back(r);
  }
  c.result.steps = 2;
  if (stepper_fields) {
    c.stepper.nu_valid = c.stepper.history_valid = true;
    c.stepper.prev_dt = c.cursor.dt;
    c.stepper.nu = smooth(n, 1, 0.0);
    c.stepper.prev_phi = smooth(n, 1, 0.49);
    c.stepper.prev_nu = smooth(n, 1, 0.01);
  }
  return c;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put(const std::string& name, const std::string& bytes) {
  std::ofstream(kDir / name, std::ios::binary) << bytes;
}

// Recomputes both CRC-32s, so that an edit reaches the checks behind them.
std::string with_checksums(std::string s) {
  std::uint64_t header = 0;
  std::memcpy(&header, s.data() + 16, 8);
  const auto* b = reinterpret_cast<const Bytef*>(s.data());
  const auto hcrc = std::uint32_t(crc32_z(0, b + 24, header));
  std::memcpy(s.data() + 12, &hcrc, 4);
  const std::size_t data = 24 + header;
  const auto dcrc = std::uint32_t(crc32_z(0, b + data, s.size() - 12 - data));
  std::memcpy(s.data() + s.size() - 12, &dcrc, 4);
  return s;
}

std::string edit(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  if (at == std::string::npos || from.size() != to.size())
    throw std::runtime_error("seed edit: no '" + from + "' or a length change");
  return s.replace(at, from.size(), to);
}

}  // namespace

int main() {
  fs::create_directories(kDir);
  const nlohmann::json params = {{"grid", 4}, {"surface", "G"}, {"volume_fraction", 0.3}};
  cmcsurf::write_checkpoint(kDir / "ok-relax-4.bin", params, state(4, false));
  cmcsurf::write_checkpoint(kDir / "ok-volume-4-stepper.bin", params, state(4, true));
  const std::string a = slurp(kDir / "ok-relax-4.bin");
  std::uint64_t header = 0;
  std::memcpy(&header, a.data() + 16, 8);
  const std::size_t data = 24 + header;

  put("bad-empty.bin", "");
  put("bad-magic.bin", "CMCSCKPX" + a.substr(8));
  put("bad-truncated.bin", a.substr(0, a.size() - 100));
  put("bad-padded.bin", with_checksums(a + std::string(8, '\0')));
  {
    std::string s = a;
    s[data + 17] ^= 0x40;
    put("bad-field-checksum.bin", s);
    s = a;
    s[30] ^= 0x01;
    put("bad-header-checksum.bin", s);
  }
  {
    std::string s = a;
    const double q = std::nan("");
    std::memcpy(s.data() + data + 8 * 5, &q, 8);
    put("bad-nan.bin", with_checksums(s));
  }
  {
    std::string s = a;
    const std::uint64_t huge = std::uint64_t(1) << 62;
    std::memcpy(s.data() + 16, &huge, 8);
    put("bad-header-length.bin", s);
  }
  put("bad-stage.bin", with_checksums(edit(a, "relax", "relay")));
  put("bad-version.bin", with_checksums(edit(a, "0.1.0", "9.1.0")));
  return 0;
}
