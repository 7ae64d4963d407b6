// Output without a whole grid on any process, under mpirun -np 2 and -np 4 (CTest label mpi):
// field.pvti with one piece per process (io/pvti.h) and checkpoints in pieces (io/checkpoint.h,
// format 5), against the serial writers bit for bit, and their failures agreed by every process.
//
// With CMCSURF_PVTI_KEEP=DIR (an existing folder), Pvti.AssembledPiecesEqualTheSerialFile also
// leaves field.pvti / serial.vti (Float64) and field32.pvti / serial32.vti (Float32) there, for
// tests/mpi/pvti_vtk.sh to open with VTK.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>

#include <fmt/core.h>

#include "../test_fields.h"
#include "io/checkpoint.h"
#include "io/pvti.h"
#include "io/run_report.h"
#include "io/vti.h"
#include "parallel/agree.h"
#include "parallel/decomposition.h"
#include "pipeline/cmc.h"

namespace cmcsurf {
namespace {

namespace fs = std::filesystem;

std::shared_ptr<const Decomposition> world() { return Decomposition::world(); }

void barrier() { world()->max(0.0); }

// A scratch folder that every process sees (rank 0 names, creates and finally removes it).
class SharedDir {
 public:
  explicit SharedDir(const char* tag) {
    double id = 0.0;
    if (world()->rank() == 0) id = double(std::random_device()() % 1000000000u);
    world()->broadcast(&id, 1);
    dir_ = fs::temp_directory_path() / fmt::format("cmcsurf-mpi-{}-{:.0f}", tag, id);
    if (world()->rank() == 0) fs::create_directories(dir_);
    barrier();
  }
  ~SharedDir() {
    barrier();
    std::error_code ec;
    if (world()->rank() == 0) fs::remove_all(dir_, ec);
  }
  const fs::path& dir() const { return dir_; }
  fs::path operator/(const std::string& name) const { return dir_ / name; }

 private:
  fs::path dir_;
};

// This process's block of a whole field, halo exchanged.
Field block_of(const Field& whole) {
  Field b(whole.n(), whole.ghost(), world());
  take_block(whole, b);
  b.exchange_halo();
  return b;
}

// Interiors equal bit for bit (same block); the verdict of every process.
bool bit_equal_everywhere(const Field& a, const Field& b) {
  bool same = a.n() == b.n() && a.size() == b.size() && a.offset() == b.offset();
  if (same)
    for_each_cell(a, [&](int i, int j, int k) {
      same = same && std::memcmp(&a(i, j, k), &b(i, j, k), sizeof(double)) == 0;
    });
  return world()->max(same ? 0.0 : 1.0) == 0.0;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The raw bytes of a cmcsurf .vti's first array (after "_" and its UInt64 byte count).
std::string first_array_bytes(const fs::path& p) {
  const std::string s = slurp(p);
  const std::size_t start = s.find("<AppendedData encoding=\"raw\">\n   _") + 34 + 8;
  std::uint64_t count = 0;
  std::memcpy(&count, s.data() + start - 8, 8);
  return s.substr(start, count);
}

std::string pvti_error(const fs::path& p) {
  try {
    read_pvti(p);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(Decomposition, FirstErrorIsTheLowestFailingRanksOnEveryRank) {
  const int r = world()->rank(), p = world()->ranks();
  int rank = -2;
  EXPECT_EQ(world()->first_error("", &rank), "");
  EXPECT_EQ(rank, -1);
  const std::string mine = r >= 1 ? fmt::format("rank {} failed", r) : "";
  EXPECT_EQ(world()->first_error(mine, &rank), "rank 1 failed");
  EXPECT_EQ(rank, 1);
  try {
    agree_or_throw(world().get(), r == p - 1 ? "disk full" : "");
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), fmt::format("process {} of {}: disk full", p - 1, p));
  }
}

TEST(Pvti, AssembledPiecesEqualTheSerialFile) {
  SharedDir tmp("pvti");
  const char* keep = std::getenv("CMCSURF_PVTI_KEEP");
  const fs::path out = keep ? fs::path(keep) : tmp.dir();
  const Field phi = testing::random_field(16, 2, -1, 1, 11);
  const Field nu = testing::random_field(16, 1, -2, 2, 12);
  const Field phi_block = block_of(phi), nu_block = block_of(nu);
  const std::map<std::string, std::string> meta = {{"surface", "G"}, {"area", "2.25"}};
  for (const bool float32 : {false, true}) {
    const std::string suffix = float32 ? "32" : "";
    const fs::path pvti = out / ("field" + suffix + ".pvti"),
                   serial = out / ("serial" + suffix + ".vti");
    write_pvti(pvti, {{"phi", &phi_block}, {"nu", &nu_block}}, float32, meta);
    if (world()->rank() == 0) write_vti(serial, {{"phi", &phi}, {"nu", &nu}}, float32, meta);
    barrier();
    // One piece per process, named by rank, in rank order.
    const std::string summary = slurp(pvti);
    for (int r = 0; r < world()->ranks(); ++r) {
      const Block b = world()->block_of(r, 16);
      const std::string line = fmt::format(
          "<Piece Extent=\"{} {} {} {} {} {}\" Source=\"field{}/piece_{:04d}.vti\"/>", b.offset[0],
          b.offset[0] + b.size[0], b.offset[1], b.offset[1] + b.size[1], b.offset[2],
          b.offset[2] + b.size[2], suffix, r);
      EXPECT_NE(summary.find(line), std::string::npos) << line << "\n" << summary;
      EXPECT_TRUE(fs::is_regular_file(pvti_piece_dir(pvti) / fmt::format("piece_{:04d}.vti", r)));
    }
    // This process's piece holds exactly the serial file's points of its extent, the last
    // layer (the next piece's first points, or the wrap) included.
    {
      const std::string piece = first_array_bytes(pvti_piece_dir(pvti) /
                                                  fmt::format("piece_{:04d}.vti", world()->rank()));
      const std::string all = first_array_bytes(serial);
      const std::size_t elem = float32 ? 4 : 8, m = 17;
      const auto& o = phi_block.offset();
      const int mx = phi_block.nx() + 1, my = phi_block.ny() + 1, mz = phi_block.nz() + 1;
      bool same = piece.size() == std::size_t(mx) * my * mz * elem;
      for (int k = 0; same && k < mz; ++k)
        for (int j = 0; j < my; ++j) {
          const std::size_t at = ((o[2] + k) * m + (o[1] + j)) * m + o[0];
          same = same && piece.compare(std::size_t(k * my + j) * mx * elem, mx * elem, all,
                                       at * elem, mx * elem) == 0;
        }
      EXPECT_TRUE(world()->max(same ? 0.0 : 1.0) == 0.0) << "points of the pieces" << suffix;
    }
    // Every process assembles the whole grid from the pieces: the serial file's values, bit for
    // bit (Float32: the same rounding).
    const VtiData a = read_pvti(pvti), b = read_vti(serial);
    EXPECT_EQ(a.metadata, b.metadata);
    for (const char* name : {"phi", "nu"})
      EXPECT_TRUE(bit_equal_everywhere(a.arrays.at(name), b.arrays.at(name))) << name << suffix;
    if (!float32) {
      EXPECT_TRUE(bit_equal_everywhere(a.arrays.at("phi"), phi));
    }
    // A process reads only its block.
    Field mine(16, 2, world());
    read_pvti_block_interior_only(pvti, "phi", mine);
    EXPECT_TRUE(bit_equal_everywhere(mine, block_of(b.arrays.at("phi"))));
  }
}

// A piece that one process cannot write: every process throws that process's error, the
// earlier summary is gone, and so are the pieces of the others.
TEST(Pvti, AFailedPieceLeavesNoSummary) {
  SharedDir tmp("pvti-fail");
  const int p = world()->ranks();
  const Field phi = block_of(testing::random_field(16, 2, 0, 1, 13));
  const fs::path pvti = tmp / "field.pvti";
  write_pvti(pvti, {{"phi", &phi}});
  const fs::path blocked = tmp / "field" / fmt::format("piece_{:04d}.vti", p - 1);
  if (world()->rank() == 0) {  // a non-empty folder where the last piece goes: its rename fails
    fs::remove(blocked);
    fs::create_directories(blocked / "inside");
  }
  barrier();
  try {
    write_pvti(pvti, {{"phi", &phi}});
    ADD_FAILURE() << "the write succeeded";
  } catch (const std::runtime_error& e) {
    const std::string why = e.what();
    EXPECT_NE(why.find(fmt::format("process {} of {}: cannot rename", p - 1, p)), std::string::npos)
        << why;
  }
  barrier();
  EXPECT_FALSE(fs::exists(pvti));
  for (int r = 0; r < p - 1; ++r)
    EXPECT_FALSE(fs::exists(tmp / "field" / fmt::format("piece_{:04d}.vti", r))) << r;
  barrier();
  if (world()->rank() == 0) fs::remove_all(blocked);
}

// Summaries that do not match their pieces (hand-edited after a good write), read on rank 0.
TEST(Pvti, RefusesSummariesThatDoNotMatchTheirPieces) {
  SharedDir tmp("pvti-hostile");
  const Field phi = block_of(testing::random_field(16, 2, 0, 1, 14));
  write_pvti(tmp / "field.pvti", {{"phi", &phi}});
  if (world()->rank() == 0) {
    const std::string good = slurp(tmp / "field.pvti");
    const std::size_t first = good.find("    <Piece "),
                      second = good.find("    <Piece ", first + 1);
    const std::size_t end_second = good.find('\n', second) + 1;
    const std::string line0 = good.substr(first, second - first);
    const std::string line1 = good.substr(second, end_second - second);
    auto refused = [&](const std::string& text, const std::string& fragment) {
      std::ofstream(tmp / "h.pvti", std::ios::binary) << text;
      const std::string why = pvti_error(tmp / "h.pvti");
      EXPECT_NE(why.find(fragment), std::string::npos) << "want '" << fragment << "' in: " << why;
    };
    ASSERT_EQ(pvti_error(tmp / "field.pvti"), "");
    refused(std::string(good).erase(second, end_second - second),
            "cells; the pieces must tile the grid");
    refused(std::string(good).replace(second, end_second - second, line0),
            "holds cell (0, 0, 0), which an earlier piece holds too");
    // Sources swapped: each file's own extent differs from the one the summary gives it.
    const auto source = [](const std::string& line) {
      const std::size_t s = line.find("Source=");
      return line.substr(s, line.find("/>") - s);
    };
    std::string swapped = good;
    swapped.replace(
        second, line1.size(),
        std::string(line1).replace(line1.find("Source="), source(line1).size(), source(line0)));
    refused(swapped, "differs from the Extent=");
    fs::rename(tmp / "field" / "piece_0001.vti", tmp / "moved.vti");
    refused(good, "piece 1 'field/piece_0001.vti' is missing");
    fs::rename(tmp / "moved.vti", tmp / "field" / "piece_0001.vti");
  }
  barrier();
}

// A short decomposed run stopped before its 12th step (all four fields present).
struct Stopped {
  RunParams params;
  Checkpoint checkpoint;
};

Stopped stopped_run() {
  Stopped s;
  s.params.surface = "G";
  s.params.volume_fraction = 0.35;
  s.params.grid = 16;
  s.params.epsilon = 0.04;
  s.params.solver.extrapolate = true;
  RunContext context;
  context.decomposition = world();
  int asked = 0;
  context.control = [&] { return ++asked == 12 ? RunControl::kStop : RunControl::kContinue; };
  try {
    run_cmc(s.params, context);
  } catch (RunInterrupted& stop) {
    s.checkpoint = std::move(stop.checkpoint);
  }
  return s;
}

Field gathered(const Field& block) {
  Field whole(block.n(), block.ghost());
  gather_field(block, whole, true);
  return whole;
}

std::vector<std::pair<const Field*, const Field*>> field_pairs(const Checkpoint& a,
                                                               const Checkpoint& b) {
  return {{&a.result.phi, &b.result.phi},
          {&a.stepper.nu, &b.stepper.nu},
          {&a.stepper.prev_phi, &b.stepper.prev_phi},
          {&a.stepper.prev_nu, &b.stepper.prev_nu}};
}

TEST(CheckpointPieces, KeepEveryBitAndNoWholeGridIsWritten) {
  SharedDir tmp("ckpt");
  const Stopped s = stopped_run();
  const Checkpoint& c = s.checkpoint;
  ASSERT_EQ(c.step, 11);
  ASSERT_FALSE(c.result.phi.whole());
  ASSERT_TRUE(c.stepper.nu_valid && c.stepper.history_valid);
  const fs::path file = tmp / "checkpoint.bin";
  const nlohmann::json params = params_json(s.params);
  write_checkpoint(file, params, c);  // collective: one piece per process
  write_checkpoint(file, params, c);  // a second: the first one's pieces go
  barrier();
  int pieces = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(checkpoint_piece_dir(file)))
    ++pieces;
  EXPECT_EQ(pieces, world()->ranks());
  // The main file holds the header alone.
  EXPECT_LT(fs::file_size(file), std::uintmax_t(16) * 16 * 16 * 8);

  // Each process reads its blocks (the piece it wrote) ...
  CheckpointReadOptions blocks;
  blocks.decomposition = world();
  const CheckpointFile mine = read_checkpoint(file, blocks);
  EXPECT_EQ(mine.checkpoint.step, c.step);
  for (const auto& [x, y] : field_pairs(c, mine.checkpoint))
    EXPECT_TRUE(bit_equal_everywhere(*x, *y));
  // ... or the whole grid from every piece (a serial resume).
  const CheckpointFile whole = read_checkpoint(file);
  for (const auto& [x, y] : field_pairs(c, whole.checkpoint)) {
    EXPECT_TRUE(y->whole());
    EXPECT_TRUE(bit_equal_everywhere(gathered(*x), *y));
  }

  // A serial checkpoint (format 4) read in blocks: the same bits.
  Checkpoint serial = c;
  serial.result.phi = gathered(c.result.phi);
  serial.stepper.nu = gathered(c.stepper.nu);
  serial.stepper.prev_phi = gathered(c.stepper.prev_phi);
  serial.stepper.prev_nu = gathered(c.stepper.prev_nu);
  if (world()->rank() == 0) write_checkpoint(tmp / "serial.bin", params, serial);
  barrier();
  const CheckpointFile from_serial = read_checkpoint(tmp / "serial.bin", blocks);
  for (const auto& [x, y] : field_pairs(c, from_serial.checkpoint))
    EXPECT_TRUE(bit_equal_everywhere(*x, *y));

  // The last process's piece damaged: only that process sees it; agreed, all refuse it.
  barrier();
  if (world()->rank() == 0) {
    for (const auto& e : fs::directory_iterator(checkpoint_piece_dir(file))) {
      const std::string name = e.path().filename().string();
      if (name.find(fmt::format("-r{:06d}.bin", world()->ranks() - 1)) == std::string::npos)
        continue;
      std::string bytes = slurp(e.path());
      bytes[bytes.size() / 2] ^= 1;
      std::ofstream(e.path(), std::ios::binary) << bytes;
    }
  }
  barrier();
  std::string error;
  try {
    read_checkpoint(file, blocks);
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  EXPECT_EQ(error.empty(), world()->rank() != world()->ranks() - 1) << error;
  int rank = -1;
  const std::string agreed = world()->first_error(error, &rank);
  EXPECT_EQ(rank, world()->ranks() - 1);
  EXPECT_NE(agreed.find("the piece is corrupted"), std::string::npos) << agreed;
}

}  // namespace
}  // namespace cmcsurf
