// Google Benchmark kernels of a finest time step outside the V-cycle: the step's start, its
// defect norms, its end (the mass restore) and the history's measures, each fused kernel beside
// its `_ref` twin (the separate passes it replaced). Bytes are each kernel's minimum traffic
// (every array read or written once, write-allocate not counted), against the triad of
// kernels_bench.cpp in the same process.
#include <benchmark/benchmark.h>

#include "cahn_hilliard/anderson.h"
#include "cahn_hilliard/operator.h"
#include "cahn_hilliard/time_step.h"
#include "grid/field.h"
#include "measure/measures.h"
#include "measure/sharp_volume.h"
#include "../tests/test_fields.h"

namespace cmcsurf {
namespace {

using testing::random_field;

double cells(int n) { return double(n) * n * n; }

void set_bytes(benchmark::State& state, int n, double per_cell) {
  state.SetBytesProcessed(int64_t(double(state.iterations()) * per_cell * cells(n)));
}

// Each fused kernel runs with ref = false, its `_ref` twin with ref = true, on the same data.

// The history's measures with the stop rule's sums: reads phi and phi^n, 16 bytes per cell.
void BM_StepMeasures(benchmark::State& state, bool ref) {
  const int n = int(state.range(0));
  const Field phi = testing::gyroid_field(n, 2), before = random_field(n, 0, 0, 1, 2);
  const auto kernel = ref ? step_measures_ref : step_measures;
  for (auto _ : state) benchmark::DoNotOptimize(kernel(phi, before, 0.02, true, 0.0));
  set_bytes(state, n, 16);
}

// The step's start as a step after a mix runs it (the history restarted, the mass taken):
// reads phi^n and nu, writes the two sources, the guess and the two history copies: 56 bytes
// per cell.
void BM_SourceFirstDefect(benchmark::State& state, bool ref) {
  const int n = int(state.range(0));
  const ChParams p{0.02, 0.5 / n, SweepOrder::kRedBlack};
  const Field phi = testing::gyroid_field(n, 2), nu = random_field(n, 1, -0.1, 0.1, 3);
  Field s1(n, 1), s2(n, 1), guess(n, 1), prev_phi(n, 0), prev_nu(n, 0);
  double m = 0.0;
  ch_source_first_defect(phi, nu, p, s1, s2, guess, {&prev_phi, &prev_nu, &m});  // first touch
  const auto kernel = ref ? ch_source_first_defect_ref : ch_source_first_defect;
  for (auto _ : state)
    benchmark::DoNotOptimize(kernel(phi, nu, p, s1, s2, guess, {&prev_phi, &prev_nu, &m}));
  set_bytes(state, n, 56);
}

// The defect norm after a V-cycle with the iterate's mean: reads 4 arrays, 32 bytes per cell.
void BM_ResidualNormMean(benchmark::State& state, bool ref) {
  const int n = int(state.range(0));
  const ChParams p{0.02, 0.5 / n, SweepOrder::kRedBlack};
  const Field phi = testing::gyroid_field(n, 1), nu = random_field(n, 1, -0.1, 0.1, 3);
  const Field r1 = random_field(n, 1, 0, 1, 4), r2(n, 1);
  double m = 0.0;
  const auto kernel = ref ? nso_residual_norm_mean_ref : nso_residual_norm_mean;
  for (auto _ : state) benchmark::DoNotOptimize(kernel(phi, nu, r1, r2, p, m));
  set_bytes(state, n, 32);
}

// The step's end: phi = solution + mass shift with phi's halo: reads one array, writes one,
// 16 bytes per cell; the fused kernel is timed with the halo exchange the step does after it.
void BM_CopyInteriorPlus(benchmark::State& state, bool ref) {
  const int n = int(state.range(0));
  const Field src = random_field(n, 1, 0, 1, 5);
  Field phi(n, 2);
  copy_interior_plus_ref(src, 1e-9, phi);  // first touch
  for (auto _ : state) {
    if (ref) {
      copy_interior_plus_ref(src, 1e-9, phi);
    } else {
      copy_interior_plus(src, 1e-9, phi);
      phi.exchange_halo();
    }
  }
  set_bytes(state, n, 16);
}

// The history's sharp volume fraction (a dual-cell sweep): reads phi, 8 bytes per cell.
void BM_SharpVolumeFraction(benchmark::State& state) {
  const int n = int(state.range(0));
  const Field phi = testing::gyroid_field(n, 2);
  for (auto _ : state) benchmark::DoNotOptimize(sharp_volume_fraction(phi));
  set_bytes(state, n, 8);
}

// The stop rule's second pass (the spread of nu around its weighted mean): reads phi, 8 bytes
// per cell.
void BM_EquilibriumSpread(benchmark::State& state) {
  const int n = int(state.range(0));
  const Field phi = testing::gyroid_field(n, 2), before(n, 0);
  const WeightedNuSums sums = step_measures(phi, before, 0.02, true).nu_sums;
  for (auto _ : state) benchmark::DoNotOptimize(equilibrium_residual(phi, 0.02, sums));
  set_bytes(state, n, 8);
}

// The Anderson mix's safeguard: the energy of the mixed field, 8 bytes per cell.
void BM_Energy(benchmark::State& state) {
  const int n = int(state.range(0));
  const Field phi = testing::gyroid_field(n, 2);
  for (auto _ : state) benchmark::DoNotOptimize(energy(phi, 0.02));
  set_bytes(state, n, 8);
}

// One Anderson mix at depth 3 with its three columns (two passes over the step's x and G and
// the float history: reads x, G, the last F and c and three dF, dG columns, writes G, the new
// dF, dG, F and c: 8 + 8 + 8 x 4 reads and 8 + 4 x 4 writes, 72 bytes per cell); the `_ref` is
// AndersonMixerRef, the test twin (plain loops over a double history), at 128^3 only.
void BM_AndersonMix(benchmark::State& state, bool ref) {
  const int n = int(state.range(0));
  const Field x = random_field(n, 0, 0, 1, 6), g0 = random_field(n, 0, 0, 1, 7);
  Field g(n, 0);
  AndersonMixer mixer(3);
  AndersonMixerRef mixer_ref(3);
  int step = 0;
  // Each mix sees another G (a step of a slowly converging map), so that the columns differ.
  auto next_g = [&] {
    const double scale = 1.0 + 1e-3 * (++step % 5);
    for_each_cell(g, [&](int i, int j, int k) { g(i, j, k) = x(i, j, k) + scale * g0(i, j, k); });
  };
  for (int warm = 0; warm < 4; ++warm) {  // fills the history's columns
    next_g();
    ref ? mixer_ref.mix(x, g) : mixer.mix(x, g);
  }
  for (auto _ : state) {
    state.PauseTiming();
    next_g();
    state.ResumeTiming();
    benchmark::DoNotOptimize(ref ? mixer_ref.mix(x, g) : mixer.mix(x, g));
  }
  set_bytes(state, n, 72);
}

// A periodic halo exchange of a field with one ghost layer (the V-cycle's levels) and with two
// (phi): copies the six faces, about 6 (n + 2g)^2 g doubles; the x faces are runs of g per row.
void BM_ExchangeHalo(benchmark::State& state) {
  const int n = int(state.range(0)), ghost = int(state.range(1));
  Field f = random_field(n, ghost, 0, 1, 8);
  for (auto _ : state) f.exchange_halo();
}

constexpr auto kMs = benchmark::kMillisecond;
BENCHMARK_CAPTURE(BM_StepMeasures, fused, false)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK_CAPTURE(BM_StepMeasures, ref, true)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK_CAPTURE(BM_SourceFirstDefect, fused, false)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK_CAPTURE(BM_SourceFirstDefect, ref, true)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK_CAPTURE(BM_ResidualNormMean, fused, false)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK_CAPTURE(BM_ResidualNormMean, ref, true)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK_CAPTURE(BM_CopyInteriorPlus, fused, false)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK_CAPTURE(BM_CopyInteriorPlus, ref, true)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_SharpVolumeFraction)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_EquilibriumSpread)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_Energy)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK_CAPTURE(BM_AndersonMix, fused, false)->Arg(128)->Arg(256)->UseRealTime()->Unit(kMs);
BENCHMARK_CAPTURE(BM_AndersonMix, ref, true)->Arg(128)->UseRealTime()->Unit(kMs);
BENCHMARK(BM_ExchangeHalo)->Args({64, 1})->Args({128, 1})->Args({128, 2})->Unit(kMs);

}  // namespace
}  // namespace cmcsurf
