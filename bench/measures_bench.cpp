// Google Benchmark of the post-solve stages: the sharp measures of the final field
// (measure/sharp_surface.h) and the CMC-quality comparison with the nodal surface
// (pipeline/sweep.h), on a gyroid-like tanh-profile field at epsilon = 0.01.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "grid/field.h"
#include "measure/sharp_surface.h"
#include "pipeline/sweep.h"
#include "surfaces/nodal_level.h"

namespace cmcsurf {
namespace {

// The nodal G at alpha = 0.4 with the equilibrium profile at epsilon = 0.01.
Field gyroid_phase_field(int n) { return nodal_tanh_profile(nodal_level_set("G", 0.4, n), 0.01); }

void BM_TanhProfileInverse(benchmark::State& state) {
  const Field phi = gyroid_phase_field(int(state.range(0)));
  Field psi = Field::like(phi, 2);
  for (auto _ : state) {
    tanh_profile_inverse(phi, psi);
    benchmark::DoNotOptimize(psi.data());
  }
}

void BM_LevelSetSurface(benchmark::State& state) {
  const Field phi = gyroid_phase_field(int(state.range(0)));
  Field psi = Field::like(phi, 2);
  tanh_profile_inverse(phi, psi);
  std::vector<CurvatureSample> samples;
  for (auto _ : state) benchmark::DoNotOptimize(level_set_surface(psi, &samples).area);
  state.counters["triangles"] = double(samples.size());
}

// What the pipeline runs once after the solve: psi, the surface, the Richardson estimate.
void BM_SharpMeasures(benchmark::State& state) {
  const Field phi = gyroid_phase_field(int(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(sharp_measures(phi).area);
}

void BM_NodalLevelSet(benchmark::State& state) {
  for (auto _ : state)
    benchmark::DoNotOptimize(nodal_level_set("G", 0.4, int(state.range(0))).level);
}

void BM_CmcQuality(benchmark::State& state) {
  const Field phi = gyroid_phase_field(int(state.range(0)));
  RunParams p;
  p.surface = "G";
  p.volume_fraction = 0.4;
  p.grid = int(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(measure_cmc_quality(phi, p).nodal.std);
}

BENCHMARK(BM_TanhProfileInverse)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LevelSetSurface)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SharpMeasures)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NodalLevelSet)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CmcQuality)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cmcsurf
