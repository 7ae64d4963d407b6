// Checkpoint and resume (docs/reliability.md): a run stopped before any step and continued from
// its checkpoint, written to checkpoint.bin and read back, ends bit for bit where the
// uninterrupted run ends, in every stage of the algorithm and in both modes.
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <fstream>
#include <vector>

#include "io/checkpoint.h"
#include "io/run_report.h"
#include "model/run_options.h"
#include "pipeline/cmc.h"
#include "support/temp_dir.h"

namespace cmcsurf {
namespace {

RunParams faithful_gyroid() {  // every stage: prerelax, relax, volume corrections
  RunParams p;
  p.surface = "G";
  p.volume_fraction = 0.35;
  p.grid = 16;
  p.epsilon = 0.04;
  p.tol = 1e-6;
  p.volume_tol = 1e-5;
  return p;
}

RunParams fast_gyroid() {  // coarse-to-fine, extrapolation, adaptive dt, relative V-cycle stop
  RunParams p = faithful_gyroid();
  p.grid = 32;
  p.epsilon = 0.03;
  p.coarse_levels = 1;
  p.solver.rtol = 1e-2;
  p.solver.extrapolate = true;
  p.dt_max_factor = 8.0;
  p.settle_tol = 1e-5;
  p.fast = true;
  return p;
}

RunParams sphere() {  // a direct relaxation
  RunParams p;
  p.surface = "sphere";
  p.grid = 16;
  p.epsilon = 0.04;
  p.radius = 0.4;  // a smaller ball dissolves on this coarse grid (no surface is an error)
  p.tol = 1e-6;
  p.max_steps = 60;
  return p;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_field(const Field& a, const Field& b) {
  ASSERT_EQ(a.n(), b.n());
  long differ = 0;
  for (int k = 0; k < a.nz(); ++k)
    for (int j = 0; j < a.ny(); ++j)
      for (int i = 0; i < a.nx(); ++i) differ += !same_bits(a(i, j, k), b(i, j, k));
  EXPECT_EQ(differ, 0) << "cells whose bits differ";
}

// Everything but the wall-clock timings.
void expect_same_run(const RunResult& a, const RunResult& b) {
  expect_same_field(a.phi, b.phi);
  ASSERT_EQ(a.history.size(), b.history.size());
  for (std::size_t s = 0; s < a.history.size(); ++s) {
    const StepRecord &x = a.history[s], &y = b.history[s];
    EXPECT_EQ(x.step, y.step);
    EXPECT_EQ(stage_text(x), stage_text(y)) << "step " << x.step;
    EXPECT_EQ(x.vcycles, y.vcycles) << "step " << x.step;
    for (auto [u, v] : {std::pair{x.time, y.time}, {x.dt, y.dt}, {x.area, y.area},
                        {x.d_area, y.d_area}, {x.d_phi, y.d_phi}, {x.energy, y.energy},
                        {x.mass, y.mass}, {x.residual, y.residual}})
      EXPECT_TRUE(same_bits(u, v)) << "step " << x.step << ": " << u << " vs " << v;
  }
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.volume_steps, b.volume_steps);
  EXPECT_EQ(a.prerelax_steps, b.prerelax_steps);
  EXPECT_EQ(a.coarse_steps, b.coarse_steps);
  EXPECT_EQ(a.vcycles, b.vcycles);
  EXPECT_EQ(a.unconverged_steps, b.unconverged_steps);
  EXPECT_EQ(a.converged, b.converged);
  EXPECT_EQ(a.stop_reason, b.stop_reason);
  EXPECT_EQ(a.volume_iterates.size(), b.volume_iterates.size());
  EXPECT_EQ(a.volume_converged, b.volume_converged);
  // The reports agree to the last digit (timings apart).
  nlohmann::json ja = run_report(RunParams{}, a, 1), jb = run_report(RunParams{}, b, 1);
  // Timings, and the process's peak memory (the whole process's, not the run's: the resumed
  // run read a checkpoint, and under ASan the allocator's own pools move it).
  for (const char* key : {"wall_seconds", "solver_seconds", "measure_seconds", "geometry_seconds",
                          "volume_seconds",
                          "seconds_per_vcycle", "timings", "peak_memory_bytes",
                          "peak_memory_bytes_per_cell"}) {
    ja.erase(key);
    jb.erase(key);
  }
  EXPECT_EQ(ja.dump(), jb.dump());
}

// Stops the run before its `at`-th time step (counting from 1) and returns the checkpoint,
// written to disk and read back.
Checkpoint stop_before(const RunParams& p, int at, const TempDir& tmp) {
  RunContext context;
  int asked = 0;
  context.control = [&] { return ++asked == at ? RunControl::kStop : RunControl::kContinue; };
  try {
    run_cmc(p, context);
  } catch (RunInterrupted& stop) {
    const auto path = tmp / kCheckpointFileName;
    write_checkpoint(path, params_json(p), stop.checkpoint);
    CheckpointFile f = read_checkpoint(path);
    EXPECT_EQ(f.params, params_json(p));
    return std::move(f.checkpoint);
  }
  ADD_FAILURE() << "the run ended before step " << at;
  return {};
}

RunResult resume(const RunParams& p, Checkpoint c) {
  RunContext context;
  context.resume = std::make_shared<const Checkpoint>(std::move(c));
  return run_cmc(p, context);
}

void check_resumes(const RunParams& p, std::vector<std::string> want_stages) {
  const RunResult whole = run_cmc(p);
  const int steps = int(whole.history.size());
  TempDir tmp("cmcsurf-resume");
  // A stop before every stage's first and second step, and half-way through each stage.
  std::vector<int> at;
  for (int s = 0; s < steps; ++s) {
    const bool first =
        s == 0 || stage_text(whole.history[s]) != stage_text(whole.history[s - 1]);
    if (first) at.insert(at.end(), {s + 1, s + 2});
  }
  at.push_back(steps / 2);
  at.push_back(steps);  // before the last step
  std::set<std::string> seen;
  for (int k : at) {
    if (k < 1 || k > steps) continue;
    SCOPED_TRACE(::testing::Message() << p.surface << " N " << p.grid << ": stopped before step "
                                      << k << " (" << stage_text(whole.history[k - 1]) << ")");
    Checkpoint c = stop_before(p, k, tmp);
    seen.insert(std::string(run_stage_name(c.cursor.stage)) + "@" +
                std::to_string(c.cursor.grid));
    expect_same_run(resume(p, std::move(c)), whole);
  }
  for (const std::string& s : want_stages) EXPECT_TRUE(seen.count(s)) << "no stop in " << s;
}

TEST(Resume, FaithfulRunEndsOnTheSameBitsFromEveryStage) {
  check_resumes(faithful_gyroid(), {"prerelax@16", "relax@16", "volume@16"});
}

TEST(Resume, FastRunEndsOnTheSameBitsFromEveryStageAndGrid) {
  check_resumes(fast_gyroid(), {"prerelax@16", "relax@16", "relax@32", "volume@32"});
}

TEST(Resume, DirectRelaxationEndsOnTheSameBits) { check_resumes(sphere(), {"relax@16"}); }

// Periodic checkpoints leave the run itself untouched.
TEST(Resume, CheckpointsDoNotChangeTheRun) {
  const RunParams p = fast_gyroid();
  const RunResult plain = run_cmc(p);
  RunContext context;
  int calls = 0, written = 0;
  context.control = [&] {
    return ++calls % 3 == 0 ? RunControl::kCheckpoint : RunControl::kContinue;
  };
  context.checkpoint = [&](const Checkpoint& c) {
    ++written;
    EXPECT_EQ(c.step + 1, calls);
  };
  expect_same_run(run_cmc(p, context), plain);
  EXPECT_GT(written, 5);
}

RunParams mixing_gyroid() {  // the fast mode as the command line sets it: Anderson mixing
  RunParams p;
  p.surface = "G";
  p.volume_fraction = 0.35;
  p.grid = 32;
  finish_run_params(p, RunChoices{}, true);
  return p;
}

// The uninterrupted mixing run, and the steps (counting from 1) before which its mixer holds
// history, found by a checkpoint before every step (which must leave the run as it was).
struct MixingRun {
  RunParams params = mixing_gyroid();
  RunResult whole;
  std::vector<int> mixing;  // steps before which the mixer holds columns
  int first_full_relax = 0;   // the first of them with every ring slot a column, in step 6
  int first_full_volume = 0;  // ... in a relaxation after a mass correction
};

const MixingRun& mixing_run() {
  static const MixingRun m = [] {
    MixingRun m;
    m.whole = run_cmc(m.params);
    RunContext context;
    context.control = [] { return RunControl::kCheckpoint; };
    context.checkpoint = [&](const Checkpoint& c) {
      if (!c.anderson || c.anderson->columns == 0) return;
      m.mixing.push_back(c.step + 1);
      int& full = c.cursor.stage == RunStage::kRelax ? m.first_full_relax : m.first_full_volume;
      if (c.anderson->columns == c.anderson->depth && full == 0) full = c.step + 1;
    };
    expect_same_run(run_cmc(m.params, context), m.whole);
    return m;
  }();
  return m;
}

// Stopped while the mixer holds history (its first column; the ring full, in step 6 and after
// a mass correction), written, read and resumed, the run ends on the bits of the uninterrupted
// one: the checkpoint carries the mixer's history. (Resumed with a fresh mixer instead, each of
// these stops ends elsewhere: 32768 of 32768 cells differ, 35 to 46 steps against 44.)
TEST(Resume, FastRunStoppedWhileMixingEndsOnTheSameBits) {
  const MixingRun& m = mixing_run();
  ASSERT_EQ(m.params.anderson_depth, 3);
  ASSERT_FALSE(m.mixing.empty());
  ASSERT_GT(m.first_full_relax, 0) << "the ring never filled in step 6";
  ASSERT_GT(m.first_full_volume, 0) << "the ring never filled after a mass correction";
  TempDir tmp("cmcsurf-resume-mixing");
  for (const int k : {m.mixing.front(), m.first_full_relax, m.first_full_volume}) {
    SCOPED_TRACE(::testing::Message() << "stopped before step " << k << " ("
                                      << stage_text(m.whole.history[k - 1]) << ")");
    Checkpoint c = stop_before(m.params, k, tmp);
    ASSERT_TRUE(c.anderson_carried);
    ASSERT_TRUE(c.anderson && c.anderson->columns > 0);
    expect_same_run(resume(m.params, std::move(c)), m.whole);
  }
}

// A checkpoint of format 4 (before the mixer's history) still resumes: the mixing starts
// afresh, the run ends on the same surface within the stop rules' tolerances (not the same
// bits), and its warnings say so.
TEST(Resume, CheckpointWithoutTheMixerStartsItAfreshAndSaysSo) {
  const MixingRun& m = mixing_run();
  TempDir tmp("cmcsurf-resume-format4");
  const int k = m.first_full_relax;
  ASSERT_GT(k, 0);
  Checkpoint c = stop_before(m.params, k, tmp);
  c.anderson.reset();
  const auto path = tmp / "old.bin";
  write_checkpoint(path, params_json(m.params), c);
  {  // The format 4 file is this one without the mixer's section: its format word says 4.
    std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
    f.seekp(8);
    const std::uint32_t four = 4;
    f.write(reinterpret_cast<const char*>(&four), sizeof four);
  }
  CheckpointFile old = read_checkpoint(path);
  EXPECT_FALSE(old.checkpoint.anderson_carried);
  EXPECT_FALSE(old.checkpoint.anderson);
  const RunResult r = resume(m.params, std::move(old.checkpoint));
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("mixing started afresh before step " + std::to_string(k)),
            std::string::npos)
      << r.warnings.back();
  EXPECT_TRUE(r.converged);
  long differ = 0;
  for_each_cell(r.phi, [&](int i, int j, int l) {
    differ += !same_bits(r.phi(i, j, l), m.whole.phi(i, j, l));
  });
  EXPECT_GT(differ, 0) << "the mixer's history made no difference: this test shows nothing";
  // Both runs stop at the equilibrium rule and hold the sharp volume fraction within
  // volume_tol; the surfaces they stop on then agree to about the equilibrium tolerance
  // (relative area) and to 2 volume_tol.
  EXPECT_NEAR(r.final.area, m.whole.final.area, m.params.equilibrium_tol * m.whole.final.area);
  EXPECT_NEAR(r.final.volume_fraction, m.whole.final.volume_fraction, 2 * m.params.volume_tol);
}

}  // namespace
}  // namespace cmcsurf
