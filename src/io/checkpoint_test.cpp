#include "io/checkpoint.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <vector>

#include "io/run_report.h"
#include "pipeline/cmc.h"
#include "support/temp_dir.h"

namespace cmcsurf {
namespace {

// A small checkpoint of a real run (stopped before its 12th step, with extrapolation on, so
// that all four fields are present).
struct Sample {
  RunParams params;
  Checkpoint checkpoint;
  std::vector<unsigned char> bytes;
};

const Sample& sample() {
  static const Sample s = [] {
    Sample s;
    s.params.surface = "G";
    s.params.volume_fraction = 0.35;
    s.params.grid = 16;
    s.params.epsilon = 0.04;
    s.params.solver.extrapolate = true;
    RunContext context;
    int asked = 0;
    context.control = [&] { return ++asked == 12 ? RunControl::kStop : RunControl::kContinue; };
    try {
      run_cmc(s.params, context);
    } catch (RunInterrupted& stop) {
      s.checkpoint = std::move(stop.checkpoint);
    }
    TempDir tmp("cmcsurf-ckpt");
    write_checkpoint(tmp / "c.bin", params_json(s.params), s.checkpoint);
    std::ifstream in(tmp / "c.bin", std::ios::binary);
    s.bytes.assign(std::istreambuf_iterator<char>(in), {});
    return s;
  }();
  return s;
}

std::string error_of(const std::vector<unsigned char>& bytes, CheckpointReadOptions o = {}) {
  try {
    parse_checkpoint(bytes, o, "c.bin");
  } catch (const CheckpointError& e) {
    return e.what();
  }
  return "";
}

TEST(Checkpoint, RoundTripKeepsEveryBit) {
  const Sample& s = sample();
  ASSERT_TRUE(s.checkpoint.stepper.nu_valid);
  ASSERT_TRUE(s.checkpoint.stepper.history_valid);
  const CheckpointFile f = parse_checkpoint(s.bytes);
  EXPECT_EQ(f.version, CMCSURF_VERSION);
  EXPECT_EQ(f.params, params_json(s.params));
  const Checkpoint& a = s.checkpoint;
  const Checkpoint& b = f.checkpoint;
  EXPECT_EQ(b.step, 11);
  EXPECT_EQ(b.cursor.stage, a.cursor.stage);
  EXPECT_EQ(b.cursor.dt, a.cursor.dt);
  EXPECT_EQ(b.cursor.area, a.cursor.area);
  EXPECT_EQ(b.result.history.size(), a.result.history.size());
  EXPECT_EQ(b.result.history.back().residual, a.result.history.back().residual);
  EXPECT_TRUE(std::isnan(b.result.initial.area_error) == std::isnan(a.result.initial.area_error));
  EXPECT_EQ(b.stepper.prev_dt, a.stepper.prev_dt);
  for (auto [x, y] : {std::pair{&a.result.phi, &b.result.phi}, {&a.stepper.nu, &b.stepper.nu},
                      {&a.stepper.prev_phi, &b.stepper.prev_phi},
                      {&a.stepper.prev_nu, &b.stepper.prev_nu}})
    for_each_cell(*x, [&](int i, int j, int k) { ASSERT_EQ((*x)(i, j, k), (*y)(i, j, k)); });
}

// The equilibrium rule's residual of each step travels in the history, "not measured" (NaN)
// included; a step written before the column existed reads as not measured.
TEST(Checkpoint, HistoryKeepsTheEquilibriumResidual) {
  const Sample& s = sample();
  ASSERT_GE(s.checkpoint.result.history.size(), 2u);
  Checkpoint c = s.checkpoint;
  c.result.history[0].equilibrium_residual = 1.0 / 3.0 * 1e-3;
  c.result.history[1].equilibrium_residual = std::nan("");
  TempDir tmp("cmcsurf-ckpt");
  write_checkpoint(tmp / "e.bin", params_json(s.params), c);
  const Checkpoint back = read_checkpoint(tmp / "e.bin").checkpoint;
  EXPECT_EQ(back.result.history[0].equilibrium_residual, 1.0 / 3.0 * 1e-3);
  EXPECT_TRUE(std::isnan(back.result.history[1].equilibrium_residual));

  nlohmann::json older = c.result.history[0];
  ASSERT_TRUE(older.contains("equilibrium_residual"));
  older.erase("equilibrium_residual");
  StepRecord r = older.get<StepRecord>();
  EXPECT_TRUE(std::isnan(r.equilibrium_residual));
  EXPECT_EQ(r.area, c.result.history[0].area);
  EXPECT_EQ(r.step, c.result.history[0].step);
  // A null (JSON's form of a NaN) reads as not measured too.
  older["equilibrium_residual"] = nullptr;
  EXPECT_TRUE(std::isnan(older.get<StepRecord>().equilibrium_residual));
}

// A mixer's state as a run holds it: depth 3, two columns in ring slots 2 and 0 (the ring
// wrapped), slot 1 stale; values whose decimal forms are not exact.
AndersonState sample_mixer(std::size_t cells) {
  AndersonState m;
  m.depth = 3;
  m.columns = 2;
  m.newest = 0;
  m.have_prev = true;
  m.prev_c.resize(cells);
  m.prev_f.resize(cells);
  m.dg.assign(3, std::vector<float>(cells));
  m.df = m.dg;
  for (std::size_t i = 0; i < cells; ++i) {
    m.prev_c[i] = float(1.0 / (3.0 + double(i)) * 1e-5);
    m.prev_f[i] = float(-std::sqrt(double(i)) * 1e-7);
    for (int s = 0; s < 3; ++s) {
      m.dg[std::size_t(s)][i] = float(std::sin(double(i + 7 * s)) * 1e-5);
      m.df[std::size_t(s)][i] = float(std::cos(double(i * 3 + s)) * 1e-6);
    }
  }
  for (int r = 0; r < 9; ++r) m.gram.push_back(0.1 * r + 1.0 / 3.0);
  m.dg_mean = {1e-17 / 3.0, -2.0 / 7.0 * 1e-18, 0.0};
  m.prev_c_mean = -1e-16 / 3.0;
  m.last_residual = std::sqrt(2.0) * 1e-4;
  return m;
}

void expect_same_mixer(const AndersonState& a, const AndersonState& b) {
  EXPECT_EQ(b.depth, a.depth);
  EXPECT_EQ(b.columns, a.columns);
  EXPECT_EQ(b.newest, a.newest);
  EXPECT_EQ(b.have_prev, a.have_prev);
  EXPECT_EQ(b.gram, a.gram);  // every double exactly (CBOR keeps them)
  EXPECT_EQ(b.dg_mean, a.dg_mean);
  EXPECT_EQ(b.last_residual, a.last_residual);
  EXPECT_EQ(b.prev_c, a.prev_c);
  EXPECT_EQ(b.prev_c_mean, a.prev_c_mean);
  EXPECT_EQ(b.prev_f, a.prev_f);
  for (const int s : a.column_slots()) {
    EXPECT_EQ(b.dg[std::size_t(s)], a.dg[std::size_t(s)]) << "slot " << s;
    EXPECT_EQ(b.df[std::size_t(s)], a.df[std::size_t(s)]) << "slot " << s;
  }
  EXPECT_TRUE(b.dg[1].empty() && b.df[1].empty()) << "the stale slot travelled";
}

// The mixer's state through the file, whole and in pieces: every value's bits back, 16 + 8
// bytes per cell per column; a damaged mixer section is refused by name; a file of format 4
// (no mixer) still reads, marked so.
TEST(Checkpoint, CarriesTheAndersonMixer) {
  const Sample& s = sample();
  TempDir tmp("cmcsurf-ckpt");
  Checkpoint c = s.checkpoint;
  c.anderson = sample_mixer(c.result.phi.interior_size());
  const nlohmann::json params = params_json(s.params);
  write_checkpoint(tmp / "m.bin", params, c);
  const CheckpointFile f = read_checkpoint(tmp / "m.bin");
  ASSERT_TRUE(f.checkpoint.anderson);
  EXPECT_TRUE(f.checkpoint.anderson_carried);
  expect_same_mixer(*c.anderson, *f.checkpoint.anderson);
  std::ifstream in(tmp / "m.bin", std::ios::binary);
  const std::vector<unsigned char> good(std::istreambuf_iterator<char>(in), {});
  std::uint64_t length = 0;  // of the header
  std::memcpy(&length, good.data() + 16, 8);
  // After the header: the four fields (8 bytes a cell each), the mixer's last correction and F
  // (8) and its two columns' dG and dF (8 each), then the trailer.
  EXPECT_EQ(good.size() - 24 - length - 12, std::uint64_t(16 * 16 * 16) * (4 * 8 + 8 + 8 * 2));
  write_checkpoint(tmp / "checkpoint.bin", params, c, nlohmann::json::object(), true);
  const CheckpointFile p = read_checkpoint(tmp / "checkpoint.bin");
  ASSERT_TRUE(p.checkpoint.anderson);
  expect_same_mixer(*c.anderson, *p.checkpoint.anderson);

  auto error_with = [&](const std::function<void(Checkpoint&)>& edit) {
    Checkpoint e = c;
    edit(e);
    write_checkpoint(tmp / "h.bin", params, e);
    try {
      read_checkpoint(tmp / "h.bin");
    } catch (const CheckpointError& x) {
      return std::string(x.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_with([](Checkpoint&) {}), "");
  const std::string nan = error_with([](Checkpoint& e) { e.anderson->dg[2][5] = std::nanf(""); });
  EXPECT_NE(nan.find("field 'anderson_dg2' holds a non-finite value at cell (5, 0, 0)"),
            std::string::npos)
      << nan;

  // The header edited behind a valid checksum: counts that contradict the arrays.
  auto with_header = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json h =
        nlohmann::json::from_cbor(good.begin() + 24, good.begin() + 24 + long(length));
    edit(h["anderson"]);
    const std::vector<std::uint8_t> header = nlohmann::json::to_cbor(h);
    std::vector<unsigned char> out(good.begin(), good.begin() + 24);
    const std::uint32_t crc = std::uint32_t(::crc32_z(0, header.data(), header.size()));
    const std::uint64_t size = header.size();
    std::memcpy(out.data() + 12, &crc, 4);
    std::memcpy(out.data() + 16, &size, 8);
    out.insert(out.end(), header.begin(), header.end());
    out.insert(out.end(), good.begin() + 24 + long(length), good.end());
    return error_of(out);
  };
  EXPECT_EQ(with_header([](nlohmann::json&) {}), "");
  EXPECT_NE(with_header([](nlohmann::json& m) { m["columns"] = 4; }).find("4 column(s)"),
            std::string::npos);
  EXPECT_NE(with_header([](nlohmann::json& m) { m["newest"] = 1; })
                .find("field 6 is 'anderson_dg2' on 16^3 with 4 bytes a value; expected "
                      "'anderson_dg0'"),
            std::string::npos);
  EXPECT_NE(with_header([](nlohmann::json& m) { m["gram"][4] = std::nan(""); })
                .find("Anderson mixer is not one a run holds: a non-finite Gram"),
            std::string::npos);
  EXPECT_NE(with_header([](nlohmann::json& m) { m["last_residual"] = -1.0; })
                .find("last residual -1"),
            std::string::npos);
  EXPECT_NE(with_header([](nlohmann::json& m) { m["depth"] = 0; }).find("depth 0 outside"),
            std::string::npos);
  EXPECT_NE(with_header([](nlohmann::json& m) { m.erase("gram"); }).find("gram"),
            std::string::npos);
  EXPECT_NE(with_header([](nlohmann::json& m) { m = nullptr; }).find("fields listed"),
            std::string::npos);

  // Format 4: the same container without the mixer's section; read, marked as not carrying it.
  std::vector<unsigned char> old = s.bytes;
  ASSERT_EQ(old[8], kCheckpointFormat);
  EXPECT_TRUE(parse_checkpoint(old).checkpoint.anderson_carried);
  old[8] = 4;
  const CheckpointFile o = parse_checkpoint(old);
  EXPECT_FALSE(o.checkpoint.anderson_carried);
  EXPECT_FALSE(o.checkpoint.anderson);
  EXPECT_EQ(o.checkpoint.step, 11);
}

TEST(Checkpoint, RefusesTruncatedCorruptedAndForeignFiles) {
  const std::vector<unsigned char>& good = sample().bytes;
  EXPECT_EQ(error_of(good), "");
  for (std::size_t keep : {std::size_t(0), std::size_t(10), good.size() / 2, good.size() - 1}) {
    const std::vector<unsigned char> cut(good.begin(), good.begin() + keep);
    EXPECT_NE(error_of(cut), "") << "truncated to " << keep;
  }
  std::vector<unsigned char> b = good;
  b[0] = 'X';
  EXPECT_NE(error_of(b).find("not a cmcsurf checkpoint"), std::string::npos);
  b = good;
  b[8] = 9;  // format
  EXPECT_NE(error_of(b).find("format 9"), std::string::npos);
  b = good;
  b[40] ^= 1;  // inside the header
  EXPECT_NE(error_of(b).find("header's checksum"), std::string::npos);
  b = good;
  b[b.size() - 100] ^= 1;  // inside the last field
  EXPECT_NE(error_of(b).find("fields' checksum"), std::string::npos);
  b = good;
  b.push_back(0);
  EXPECT_NE(error_of(b).find("truncated or padded"), std::string::npos);
  CheckpointReadOptions other;
  other.require_version = "0.0.1";
  EXPECT_NE(error_of(good, other).find("a run resumes only with the version"), std::string::npos);
  CheckpointReadOptions small;
  small.max_n = 8;
  EXPECT_NE(error_of(good, small).find("grid 16 outside"), std::string::npos);
}

// A checkpoint of another build (compiler, flags or commit) is refused, naming both builds.
TEST(Checkpoint, RefusesAnotherBuildNamingBoth) {
  const std::vector<unsigned char>& good = sample().bytes;
  EXPECT_EQ(parse_checkpoint(good).build, build_identity());
  CheckpointReadOptions other;
  other.require_build = "cmcsurf 0.1.0 (commit 000000000000, GNU 1.0, Release: -O0, x86-64)";
  const std::string why = error_of(good, other);
  EXPECT_NE(why.find("written by " + build_identity()), std::string::npos) << why;
  EXPECT_NE(why.find("this is " + other.require_build), std::string::npos) << why;
  EXPECT_NE(build_identity().find(build_info().commit), std::string::npos);
  EXPECT_NE(build_identity().find(build_info().flags), std::string::npos);
}

// Valid checksums, hostile contents: parameters outside the command line's ranges, a stage
// grid that is no level of the run, seconds no clock holds. Each is refused by name.
TEST(Checkpoint, RefusesHostileContentsBehindValidChecksums) {
  const Sample& s = sample();
  TempDir tmp("cmcsurf-ckpt");
  auto error_with = [&](nlohmann::json params, const std::function<void(Checkpoint&)>& edit) {
    Checkpoint c = s.checkpoint;
    edit(c);
    write_checkpoint(tmp / "h.bin", params, c);
    try {
      read_checkpoint(tmp / "h.bin");
    } catch (const CheckpointError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const nlohmann::json p = params_json(s.params);
  auto with = [&](const char* key, nlohmann::json value) {
    nlohmann::json q = p;
    q[key] = std::move(value);
    return q;
  };
  const auto same = [](Checkpoint&) {};
  EXPECT_EQ(error_with(p, same), "");
  EXPECT_NE(error_with(with("epsilon", 2.0), same).find("--epsilon: got 2"), std::string::npos);
  EXPECT_NE(error_with(with("tol", std::nan("")), same).find("--tol"), std::string::npos);
  EXPECT_NE(error_with(with("grid", 50), same).find("--grid"), std::string::npos);
  EXPECT_NE(error_with(with("max_vcycles", 0), same).find("--max-vcycles"), std::string::npos);
  EXPECT_NE(error_with(with("coarsest_reduction", 1.5), same).find("coarsest_reduction"),
            std::string::npos);
  EXPECT_NE(error_with(with("surface", "nonesuch"), same).find("--surface"), std::string::npos);
  EXPECT_NE(error_with(p, [](Checkpoint& c) { c.elapsed = 1e300; }).find("elapsed"),
            std::string::npos);
  // Grid 8 is a level of a 16^3 run only with a coarse level (and then its fields are 8^3).
  const std::string off_level = error_with(p, [](Checkpoint& c) {
    c.cursor.grid = 8;
    c.result.phi = Field(8, 2);
    for (Field* f : {&c.stepper.nu, &c.stepper.prev_phi, &c.stepper.prev_nu}) *f = Field(8, 1);
  });
  EXPECT_NE(off_level.find("stage grid 8 is not the run's grid 16"), std::string::npos)
      << off_level;
}

TEST(Checkpoint, ReadsFromAFileAndNamesIt) {
  TempDir tmp("cmcsurf-ckpt");
  try {
    read_checkpoint(tmp / "missing.bin");
    FAIL();
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.bin"), std::string::npos);
  }
  std::ofstream(tmp / "c.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(sample().bytes.data()),
             std::streamsize(sample().bytes.size()));
  EXPECT_EQ(read_checkpoint(tmp / "c.bin").checkpoint.step, 11);
}

// Format 7 on one process (the whole grid as one piece; tests/mpi/pvti_test.cpp writes one per
// process): the same bits back, a new id per checkpoint with the old pieces removed, and damaged,
// stale, missing or misnamed pieces refused by name.
TEST(Checkpoint, InPiecesKeepsEveryBitAndRefusesBadPieces) {
  const Sample& s = sample();
  TempDir tmp("cmcsurf-ckpt");
  const std::filesystem::path file = tmp / "checkpoint.bin";
  const std::filesystem::path parts = checkpoint_piece_dir(file);
  EXPECT_EQ(parts, tmp / "checkpoint.parts");
  auto pieces = [&] {
    std::vector<std::filesystem::path> v;
    for (const auto& e : std::filesystem::directory_iterator(parts)) v.push_back(e.path());
    return v;
  };
  auto error = [&] {
    try {
      read_checkpoint(file);
    } catch (const CheckpointError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const nlohmann::json params = params_json(s.params);
  write_checkpoint(file, params, s.checkpoint, nlohmann::json::object(), true);
  ASSERT_EQ(pieces().size(), 1u);
  const std::filesystem::path first = pieces()[0];
  std::ifstream in(file, std::ios::binary);
  std::vector<unsigned char> bytes(std::istreambuf_iterator<char>(in), {});
  EXPECT_EQ(bytes[8], kCheckpointPiecesFormat);
  const CheckpointFile f = read_checkpoint(file);
  const Checkpoint& a = s.checkpoint;
  const Checkpoint& b = f.checkpoint;
  EXPECT_EQ(b.step, a.step);
  EXPECT_EQ(b.result.history.size(), a.result.history.size());
  for (auto [x, y] : {std::pair{&a.result.phi, &b.result.phi}, {&a.stepper.nu, &b.stepper.nu},
                      {&a.stepper.prev_phi, &b.stepper.prev_phi},
                      {&a.stepper.prev_nu, &b.stepper.prev_nu}}) {
    for_each_cell(*x, [&](int i, int j, int k) { ASSERT_EQ((*x)(i, j, k), (*y)(i, j, k)); });
    EXPECT_TRUE(halo_is_current(*y));
  }
  EXPECT_NE(error_of(bytes).find("read from its folder, not from memory"), std::string::npos);

  // The next checkpoint takes a new id and removes the pieces of the one it replaced.
  const std::string old_piece = [&] {
    std::ifstream p(first, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(p), {});
  }();
  write_checkpoint(file, params, s.checkpoint, nlohmann::json::object(), true);
  ASSERT_EQ(pieces().size(), 1u);
  const std::filesystem::path piece = pieces()[0];
  EXPECT_NE(piece, first);
  EXPECT_EQ(error(), "");
  const std::string good_piece = [&] {
    std::ifstream p(piece, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(p), {});
  }();
  auto with_piece = [&](const std::string& contents) {
    std::ofstream(piece, std::ios::binary) << contents;
    return error();
  };
  EXPECT_NE(with_piece(old_piece).find("belongs to another checkpoint"), std::string::npos);
  std::string damaged = good_piece;
  damaged[100] ^= 1;
  const std::string why = with_piece(damaged);
  EXPECT_NE(why.find(piece.filename().string()), std::string::npos) << why;
  EXPECT_NE(why.find("the piece is corrupted"), std::string::npos) << why;
  EXPECT_NE(with_piece(good_piece.substr(0, 200)).find("truncated or padded"), std::string::npos);
  std::filesystem::remove(piece);
  EXPECT_NE(error().find("missing or unreadable"), std::string::npos);
  EXPECT_EQ(with_piece(good_piece), "");

  // Valid checksums around a hostile list of pieces.
  auto with_list = [&](const std::function<void(nlohmann::json&)>& edit) {
    // The header of the file on disk (the second write, whose id names `piece`), edited.
    std::ifstream now(file, std::ios::binary);
    std::vector<unsigned char> current(std::istreambuf_iterator<char>(now), {});
    std::uint64_t length = 0;
    std::memcpy(&length, current.data() + 16, 8);
    nlohmann::json h =
        nlohmann::json::from_cbor(current.begin() + 24, current.begin() + 24 + long(length));
    edit(h["pieces"]);
    const std::vector<std::uint8_t> header = nlohmann::json::to_cbor(h);
    std::string out(current.begin(), current.begin() + 24);
    const std::uint32_t crc = std::uint32_t(::crc32_z(0, header.data(), header.size()));
    const std::uint64_t size = header.size();
    std::memcpy(out.data() + 12, &crc, 4);
    std::memcpy(out.data() + 16, &size, 8);
    out.append(header.begin(), header.end());
    out.append(current.end() - 12, current.end());
    std::filesystem::path edited = tmp / "edited";
    std::filesystem::create_directories(edited);
    std::filesystem::copy(parts, edited / "checkpoint.parts",
                          std::filesystem::copy_options::overwrite_existing |
                              std::filesystem::copy_options::recursive);
    std::ofstream(edited / "checkpoint.bin", std::ios::binary) << out;
    try {
      read_checkpoint(edited / "checkpoint.bin");
    } catch (const CheckpointError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(with_list([](nlohmann::json&) {}), "");
  EXPECT_NE(with_list([](nlohmann::json& p) { p["list"][0]["file"] = "../../x.bin"; })
                .find("is named '../../x.bin'"),
            std::string::npos);
  EXPECT_NE(with_list([](nlohmann::json& p) { p["list"] = nlohmann::json::array(); })
                .find("1 to"),
            std::string::npos);
  EXPECT_NE(with_list([](nlohmann::json& p) { p["id"] = "../x"; }).find("16 hex digits"),
            std::string::npos);
  EXPECT_NE(with_list([](nlohmann::json& p) { p["list"][0]["size"] = {16, 16, 8}; })
                .find("do not tile the 16^3 grid"),
            std::string::npos);
  EXPECT_NE(with_list([](nlohmann::json& p) { p["list"][0]["offset"] = {1, 0, 0}; })
                .find("is not inside the 16^3 grid"),
            std::string::npos);
  EXPECT_NE(with_list([](nlohmann::json& p) {
              p["list"][0]["crc"] = p["list"][0]["crc"].get<std::uint32_t>() ^ 1u;
            }).find("the header records"),
            std::string::npos);
  EXPECT_NE(with_list([](nlohmann::json& p) { p["list"][0]["crc"] = -1; }).find("CRC-32"),
            std::string::npos);

  remove_checkpoint(file);
  EXPECT_FALSE(std::filesystem::exists(file));
  EXPECT_FALSE(std::filesystem::exists(parts));
  remove_checkpoint(file);  // nothing there: fine
}

}  // namespace
}  // namespace cmcsurf
