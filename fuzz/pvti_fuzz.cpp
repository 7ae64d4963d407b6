// The .pvti reader (io/pvti.h read_pvti: the summary, its pieces' extents and sources, the
// tiling, each piece file through read_vti_piece) on arbitrary files. The input is records, each
// a 4-byte little-endian length and that many bytes: the first is DIR/field.pvti, record k >= 1
// is DIR/field/piece_{k-1:04d}.vti (fuzz/make_pvti_seeds.py writes the seeds). The reader either
// returns N^3 finite values per array or throws std::runtime_error naming the problem.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <fmt/core.h>

#include "fuzz_target.h"
#include "io/pvti.h"

namespace {

namespace fs = std::filesystem;
using cmcsurf::fuzz::require;

constexpr std::size_t kMaxPieceFiles = 16;

// A folder of this process for the files of one input, removed at exit.
struct Scratch {
  fs::path dir = fs::temp_directory_path() / fmt::format("cmcsurf-pvti-fuzz-{}", ::getpid());
  Scratch() { fs::create_directories(dir / "field"); }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

void put(const fs::path& path, cmcsurf::fuzz::Input bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  require(bool(out), "cannot write the scratch file " + path.string());
}

}  // namespace

CMCSURF_FUZZ_TARGET(pvti) {
  static const Scratch scratch;
  const fs::path pvti = scratch.dir / "field.pvti";
  fs::remove(pvti);
  fs::remove_all(scratch.dir / "field");  // the pieces of the last input
  fs::create_directories(scratch.dir / "field");
  std::size_t pos = 0, record = 0;
  while (pos + 4 <= input.size() && record <= kMaxPieceFiles) {
    std::uint32_t length = 0;
    std::memcpy(&length, input.data() + pos, 4);
    pos += 4;
    const std::size_t n = std::min<std::size_t>(length, input.size() - pos);
    const fs::path path = record == 0 ? pvti
                                      : scratch.dir / fmt::format("field/piece_{:04d}.vti",
                                                                  record - 1);
    put(path, input.subspan(pos, n));
    pos += n;
    ++record;
  }
  cmcsurf::VtiReadOptions options;
  options.max_n = 32;  // a fuzz input is small; bigger N is refused before allocating
  cmcsurf::VtiData data;
  try {
    data = cmcsurf::read_pvti(pvti, options);
  } catch (const std::runtime_error&) {
    return cmcsurf::fuzz::Outcome::refused;
  }
  require(data.n >= 1 && data.n <= options.max_n, "N out of range");
  require(!data.arrays.empty(), "no arrays");
  require(data.metadata.contains(cmcsurf::kVtiLayoutKey), "no layout");
  for (const auto& [name, f] : data.arrays) {
    require(!name.empty() && f.n() == data.n, "array '" + name + "' has the wrong N");
    for (int k = 0; k < data.n; ++k)
      for (int j = 0; j < data.n; ++j)
        for (int i = 0; i < data.n; ++i)
          require(std::isfinite(f(i, j, k)), "array '" + name + "' holds a non-finite value");
    require(cmcsurf::halo_is_current(f), "array '" + name + "' has stale ghosts");
  }
  return cmcsurf::fuzz::Outcome::parsed;
}
