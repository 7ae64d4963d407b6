#include "io/checkpoint.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
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
      .write(reinterpret_cast<const char*>(sample().bytes.data()), std::streamsize(sample().bytes.size()));
  EXPECT_EQ(read_checkpoint(tmp / "c.bin").checkpoint.step, 11);
}

}  // namespace
}  // namespace cmcsurf
