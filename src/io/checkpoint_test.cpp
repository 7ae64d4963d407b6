#include "io/checkpoint.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <vector>

#include "io/run_report.h"
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
  b[8] = 7;  // format
  EXPECT_NE(error_of(b).find("format 7"), std::string::npos);
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

TEST(Checkpoint, ReadsFromAFileAndNamesIt) {
  TempDir tmp("cmcsurf-ckpt");
  try {
    read_checkpoint(tmp / "missing.bin");
    FAIL();
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.bin"), std::string::npos);
  }
  std::ofstream(tmp / "c.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(sample().bytes.data()), std::streamsize(sample().bytes.size()));
  EXPECT_EQ(read_checkpoint(tmp / "c.bin").checkpoint.step, 11);
}

}  // namespace
}  // namespace cmcsurf
