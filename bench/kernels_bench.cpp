// Google Benchmark kernels of the finest level. Each reports bytes moved per second
// (the minimum traffic of the kernel: every array read or written once), beside a
// STREAM-like triad measured in the same process.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "cahn_hilliard/operator.h"
#include "cahn_hilliard/time_step.h"
#include "grid/field.h"
#include "measure/measures.h"
#include "multigrid/transfer.h"
#include "../tests/test_fields.h"

namespace cmcsurf {
namespace {

using testing::random_field;

Field gyroid(int n, int ghost) { return testing::gyroid_field(n, ghost); }

double cells(int n) { return double(n) * n * n; }

// a = b + s c over 3 arrays of N^3 doubles: 24 bytes per cell (write-allocate not counted).
void BM_StreamTriad(benchmark::State& state) {
  const std::size_t n = std::size_t(state.range(0)) * state.range(0) * state.range(0);
  std::vector<double> a(n, 1.0), b(n, 2.0), c(n, 3.0);
  for (auto _ : state) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + 3.0 * c[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(24 * n));
}

// One red-black sweep as the V-cycle does it (halo exchange + the fused one-pass sweep): reads
// phi, nu, 2 sources, writes phi, nu: 6 arrays, 48 bytes per cell.
void BM_SmootherSweep(benchmark::State& state) {
  const int n = int(state.range(0));
  Fields u;
  u.push_back(gyroid(n, 1));
  u.push_back(random_field(n, 1, -0.01, 0.01, 2));
  Fields rhs;
  rhs.push_back(random_field(n, 1, 0, 1, 3));
  rhs.push_back(Field(n, 1));
  ChOperator op({0.01, 0.5 / n, SweepOrder::kRedBlack});
  for (auto _ : state) op.smooth(u, rhs, 1);
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(48 * cells(n)));
}

// The same sweep as two colour passes with a halo exchange between (before the fused sweep):
// every array is streamed twice, so the bytes counted are the same 48 per cell.
void BM_SmootherSweepTwoPass(benchmark::State& state) {
  const int n = int(state.range(0));
  Field phi = gyroid(n, 1), nu = random_field(n, 1, -0.01, 0.01, 2);
  const Field s1 = random_field(n, 1, 0, 1, 3), s2(n, 1);
  const ChParams p{0.01, 0.5 / n, SweepOrder::kRedBlack};
  for (auto _ : state)
    for (int colour = 0; colour < 2; ++colour) {
      phi.exchange_halo();
      nu.exchange_halo();
      smooth_color(phi, nu, s1, s2, p, colour);
    }
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(48 * cells(n)));
}

// Two sweeps as the V-cycle's pre- and post-smoothing do them: in one pass over memory
// (range(1) = 2, temporal blocking) or as two one-pass sweeps (1). The bytes counted are those
// of two unblocked sweeps, 96 per cell, so that the rates compare; one pass moves 48.
void BM_SmootherTwoSweeps(benchmark::State& state) {
  const int n = int(state.range(0)), per_pass = int(state.range(1));
  Field phi = gyroid(n, 1), nu = random_field(n, 1, -0.01, 0.01, 2);
  const Field s1 = random_field(n, 1, 0, 1, 3), s2(n, 1);
  const ChParams p{0.01, 0.5 / n, SweepOrder::kRedBlack};
  for (auto _ : state)
    for (int done = 0; done < 2; done += per_pass)
      smooth_red_black_fused(phi, nu, s1, s2, p, per_pass);
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(96 * cells(n)));
}

// Defect rhs - NSO(u): reads 4 arrays, writes 2: 48 bytes per cell.
void BM_Residual(benchmark::State& state) {
  const int n = int(state.range(0));
  Fields u{gyroid(n, 1), random_field(n, 1, -0.01, 0.01, 2)};
  Fields rhs{random_field(n, 1, 0, 1, 3), Field(n, 1)};
  Fields d{Field(n, 1), Field(n, 1)};
  ChOperator op({0.01, 0.5 / n, SweepOrder::kRedBlack});
  for (auto _ : state) op.residual(u, rhs, d);
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(48 * cells(n)));
}

// The V-cycle's defect restricted as it is formed (nso_residual_restrict): reads 4 arrays,
// writes 2 coarse ones: 34 bytes per fine cell, against 48 + 2 x 9 = 66 for BM_Residual and
// two BM_Restriction.
void BM_ResidualRestricted(benchmark::State& state) {
  const int n = int(state.range(0));
  Fields u{gyroid(n, 1), random_field(n, 1, -0.01, 0.01, 2)};
  Fields rhs{random_field(n, 1, 0, 1, 3), Field(n, 1)};
  Fields d{Field(n, 1), Field(n, 1)}, c{Field(n / 2, 1), Field(n / 2, 1)};
  ChOperator op({0.01, 0.5 / n, SweepOrder::kRedBlack});
  for (auto _ : state) op.residual_restricted(u, rhs, d, c);
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(34 * cells(n)));
}

// The stop test's defect norm without storing the defect (nso_residual_norm): reads 4 arrays,
// 32 bytes per cell, against 48 + 16 = 64 for the defect written and read back.
void BM_ResidualNorm(benchmark::State& state) {
  const int n = int(state.range(0));
  Fields u{gyroid(n, 1), random_field(n, 1, -0.01, 0.01, 2)};
  Fields rhs{random_field(n, 1, 0, 1, 3), Field(n, 1)};
  Fields d{Field(n, 1), Field(n, 1)};
  ChOperator op({0.01, 0.5 / n, SweepOrder::kRedBlack});
  for (auto _ : state) benchmark::DoNotOptimize(op.residual_norm(u, rhs, d));
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(32 * cells(n)));
}

// Restriction: reads the fine array, writes 1/8: 9 bytes per fine cell.
void BM_Restriction(benchmark::State& state) {
  const int n = int(state.range(0));
  Field fine = random_field(n, 1, 0, 1, 4), coarse(n / 2, 1);
  for (auto _ : state) restrict_average(fine, coarse);
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(9 * cells(n)));
}

// Correction: reads and writes the fine array, reads 2 coarse arrays: 18 bytes per fine cell.
void BM_Interpolation(benchmark::State& state) {
  const int n = int(state.range(0));
  Field fine = random_field(n, 1, 0, 1, 5);
  Field c = random_field(n / 2, 1, 0, 1, 6), c0 = random_field(n / 2, 1, 0, 1, 7);
  for (auto _ : state) add_interpolated_correction(c, c0, fine);
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(18 * cells(n)));
}

// Area measure: reads phi once: 8 bytes per cell.
void BM_Area(benchmark::State& state) {
  const int n = int(state.range(0));
  Field phi = gyroid(n, 2);
  for (auto _ : state) benchmark::DoNotOptimize(area(phi, 0.01));
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(8 * cells(n)));
}

// One V-cycle of the first time step from the gyroid (beta = 2), with the defect norm check
// that the stepper does after each cycle.
void BM_VCycle(benchmark::State& state) {
  const int n = int(state.range(0));
  Field phi = gyroid(n, 1);
  StepSolverOptions o;
  ChStepper stepper(n, {0.01, 0.5 / n, SweepOrder::kRedBlack}, o);
  ChOperator op(stepper.params());
  // Set up the step's source and initial guess through one (cheap) solve, then time cycles.
  o.max_vcycles = 1;
  stepper.step(phi);
  for (auto _ : state) {
    stepper.solver().vcycle(op);
    benchmark::DoNotOptimize(stepper.solver().residual_norm(op));
  }
  // Finest-level minimum traffic of the cycle before the fused defect kernels: 4 sweeps x 48 +
  // defect 48 + restriction 2x9 + correction 2x18 + norm residual 48 + 16 = 358 bytes per
  // cell; coarse levels add 1/7 of that. (Kept as the yardstick so that rates compare across
  // builds: the fused defect-restriction and norm move 4 x 48 + 34 + 9 + 36 + 32 = 303, and
  // with the sweeps in two-sweep passes 2 x 48 + 34 + 9 + 36 + 32 = 207.)
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(358 * cells(n) * 8 / 7));
}

constexpr auto kMs = benchmark::kMillisecond;
BENCHMARK(BM_StreamTriad)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_SmootherSweep)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_SmootherSweepTwoPass)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_SmootherTwoSweeps)
    ->ArgsProduct({{64, 128, 256}, {1, 2}})
    ->UseRealTime()
    ->Unit(kMs);
BENCHMARK(BM_Residual)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_ResidualRestricted)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_ResidualNorm)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_Restriction)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_Interpolation)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_Area)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_VCycle)->Arg(64)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);

}  // namespace
}  // namespace cmcsurf

BENCHMARK_MAIN();
