// resume_problem (pipeline/cmc.h): a checkpoint whose checksums are valid but whose contents do
// not fit the run that would continue it is refused by name, never continued into a failed
// CHECK, a back() on an empty vector or an overflowing counter (docs/reliability.md).
#include <gtest/gtest.h>

#include <climits>
#include <functional>
#include <string>
#include <tuple>

#include "pipeline/cmc.h"

namespace cmcsurf {
namespace {

RunParams gyroid(int grid, int coarse_levels) {
  RunParams p;
  p.surface = "G";
  p.volume_fraction = 0.35;
  p.grid = grid;
  p.epsilon = 0.04;
  p.tol = 1e-6;
  p.volume_tol = 1e-5;
  p.coarse_levels = coarse_levels;
  return p;
}

// The state before the `at`-th step whose stage is `stage`@grid (1: its first), as the run
// hands it to a periodic checkpoint.
Checkpoint stop_in(const RunParams& p, const std::string& stage, int grid, int at = 1) {
  struct Found {};
  Checkpoint found;
  int seen = 0;
  RunContext context;
  context.control = [] { return RunControl::kCheckpoint; };
  context.checkpoint = [&](const Checkpoint& c) {
    if (run_stage_name(c.cursor.stage) == stage && c.cursor.grid == grid && ++seen == at) {
      found = c;
      throw Found{};
    }
  };
  try {
    run_cmc(p, context);
  } catch (const Found&) {
    return found;
  }
  ADD_FAILURE() << "no step " << at << " in " << stage << "@" << grid;
  return {};
}

// The problem resume_problem names for the edited checkpoint, after checking that run_cmc
// refuses it the same way instead of continuing it.
std::string problem_after(const RunParams& p, Checkpoint c,
                          const std::function<void(Checkpoint&)>& edit,
                          RunEntry entry = RunEntry::kCmc) {
  edit(c);
  const std::string why = resume_problem(c, p, entry);
  if (!why.empty() && entry == RunEntry::kCmc) {
    RunContext context;
    context.resume = std::make_shared<const Checkpoint>(c);
    EXPECT_THROW(run_cmc(p, context), std::invalid_argument) << why;
  }
  return why;
}

TEST(ResumeCheck, AcceptsTheRunsOwnCheckpoints) {
  const RunParams fine = gyroid(16, 0), coarse = gyroid(32, 1);
  for (const auto& [p, stage, grid] :
       {std::tuple{fine, "prerelax", 16}, {fine, "relax", 16}, {fine, "volume", 16},
        {coarse, "prerelax", 16}, {coarse, "volume", 16}, {coarse, "relax", 32}}) {
    const Checkpoint c = stop_in(p, stage, grid, 2);
    EXPECT_EQ(run_stage_name(c.cursor.stage), stage);
    EXPECT_EQ(resume_problem(c, p, RunEntry::kCmc), "") << stage << "@" << grid;
  }
}

// A mixer's history only where the run mixes, at its depth, over the stage's cells.
TEST(ResumeCheck, RefusesAMixerTheRunDoesNotHold) {
  RunParams p = gyroid(16, 0);
  p.equilibrium_tol = 1e-2;
  p.anderson_depth = 3;
  const Checkpoint c = stop_in(p, "relax", 16, 2);
  ASSERT_EQ(resume_problem(c, p, RunEntry::kCmc), "");
  ASSERT_TRUE(c.anderson);  // a fresh mixer: no history yet, but carried
  EXPECT_EQ(c.anderson->columns, 0);
  const auto with_history = [](Checkpoint& e) {
    AndersonState& m = *e.anderson;
    const std::size_t cells = e.result.phi.interior_size();
    m.have_prev = true;
    m.columns = 1;
    m.newest = 0;
    m.prev_c.assign(cells, 0.0f);
    m.prev_f.assign(cells, 0.0f);
    m.dg[0].assign(cells, 0.0f);
    m.df[0].assign(cells, 0.0f);
  };
  EXPECT_EQ(problem_after(p, c, with_history), "");
  EXPECT_NE(problem_after(p, c, [&](Checkpoint& e) {
              with_history(e);
              e.anderson->prev_f.pop_back();
            }).find("its Anderson mixer: the last step's correction and F hold 4096 and 4095 "
                    "cells"),
            std::string::npos);
  RunParams deeper = p;
  deeper.anderson_depth = 4;
  EXPECT_NE(problem_after(deeper, c, with_history).find("has depth 3; this run's has 4"),
            std::string::npos);
  RunParams plain = p;
  plain.anderson_depth = 0;
  EXPECT_NE(problem_after(plain, c, with_history).find("this run does not mix"),
            std::string::npos);
}

TEST(ResumeCheck, RefusesAVolumeStageWithoutItsIterates) {
  const RunParams p = gyroid(16, 0);
  const Checkpoint c = stop_in(p, "volume", 16);
  ASSERT_EQ(resume_problem(c, p, RunEntry::kCmc), "");
  // constrain_volume reads volume_iterates.back(): an empty list must never reach it.
  EXPECT_NE(problem_after(p, c, [](Checkpoint& x) { x.result.volume_iterates.clear(); })
                .find("volume iterates"),
            std::string::npos);
  EXPECT_NE(
      problem_after(p, c, [&](Checkpoint& x) { x.cursor.correction = p.max_volume_corrections; })
          .find("mass correction"),
      std::string::npos);
  EXPECT_NE(problem_after(p, c, [](Checkpoint& x) { x.cursor.slope = 0.0; }).find("slope"),
            std::string::npos);
  // A run held at its mass has no volume stage.
  RunParams mass = p;
  mass.constrain = Constraint::kMass;
  EXPECT_NE(resume_problem(c, mass, RunEntry::kCmc).find("stage 'volume'"), std::string::npos);
}

TEST(ResumeCheck, RefusesAGridTheRunDoesNotPassThrough) {
  const RunParams p = gyroid(32, 1);
  const Checkpoint c = stop_in(p, "prerelax", 16);
  ASSERT_EQ(resume_problem(c, p, RunEntry::kCmc), "");
  // The same state for a run without the coarse level, for a direct relaxation and for a
  // sweep's continued member (neither has coarse levels): the CHECKs in restore() and
  // resumed_result() are never reached.
  EXPECT_NE(resume_problem(c, gyroid(32, 0), RunEntry::kCmc).find("grid 16 is not one"),
            std::string::npos);
  RunParams sphere = p;
  sphere.surface = "sphere";
  EXPECT_NE(resume_problem(c, sphere, RunEntry::kCmc).find("grid 16 is not one"),
            std::string::npos);
  EXPECT_NE(resume_problem(c, p, RunEntry::kRelaxToVolume).find("grid 16 is not one"),
            std::string::npos);
  RunContext context;
  context.resume = std::make_shared<const Checkpoint>(c);
  EXPECT_THROW(relax_to_volume_fraction(Field(), p, context), std::invalid_argument);
  // Pre-relaxation happens on the coarsest grid only.
  const Checkpoint fine = stop_in(p, "relax", 32);
  EXPECT_NE(problem_after(p, fine, [](Checkpoint& x) { x.cursor.stage = RunStage::kPrerelax; })
                .find("stage 'prerelax' on grid 32"),
            std::string::npos);
}

TEST(ResumeCheck, RefusesCountsThatOverflowOrContradictTheHistory) {
  const RunParams p = gyroid(16, 0);
  const Checkpoint c = stop_in(p, "relax", 16, 3);
  ASSERT_EQ(resume_problem(c, p, RunEntry::kCmc), "");
  EXPECT_NE(problem_after(p, c, [](Checkpoint& x) {
              x.step = INT_MAX;  // ++step_ would overflow
              x.result.history.back().step = INT_MAX;
            }).find("in the history"),
            std::string::npos);
  EXPECT_NE(problem_after(p, c, [](Checkpoint& x) { x.result.vcycles = LONG_MAX; })
                .find("V-cycles counted"),
            std::string::npos);
  EXPECT_NE(problem_after(p, c, [](Checkpoint& x) { x.result.steps = INT_MAX; })
                .find("step count"),
            std::string::npos);
  RunParams fewer = p;  // a run that stops before the cursor's step
  fewer.max_steps = c.cursor.stage_steps;
  EXPECT_NE(resume_problem(c, fewer, RunEntry::kCmc).find("relax step 2 of at most 2"),
            std::string::npos);
  EXPECT_NE(problem_after(p, c, [](Checkpoint& x) { x.cursor.dt *= 1000.0; }).find("time step"),
            std::string::npos);
  // Seconds that the clock's integer nanoseconds cannot hold.
  EXPECT_NE(problem_after(p, c, [](Checkpoint& x) { x.elapsed = 1e300; }).find("elapsed"),
            std::string::npos);
}

}  // namespace
}  // namespace cmcsurf
