// Google Benchmark of the post-solve stages: the sharp measures of the final field
// (measure/sharp_surface.h, its components), the CMC-quality comparison with the nodal surface
// (pipeline/sweep.h) and the preview (its surfaces and picture), on a gyroid-like tanh-profile
// field at epsilon = 0.01.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "grid/field.h"
#include "measure/sharp_surface.h"
#include "measure/topology.h"
#include "pipeline/preview.h"
#include "pipeline/sweep.h"
#include "render/raster.h"
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

// The final field's components (measures), the kernel and its plain twin.
void BM_PhaseComponents(benchmark::State& state, bool ref) {
  const Field phi = gyroid_phase_field(int(state.range(0)));
  const auto kernel = ref ? phase_components_ref : phase_components;
  for (auto _ : state) benchmark::DoNotOptimize(kernel(phi, 0.5).interfaces);
}

void BM_EulerCharacteristic(benchmark::State& state, bool ref) {
  const Field phi = gyroid_phase_field(int(state.range(0)));
  const auto kernel = ref ? euler_characteristic_ref : euler_characteristic;
  for (auto _ : state) benchmark::DoNotOptimize(kernel(phi, 0.5));
}

// The preview stage's two parts: the drawn surfaces (relaxed and nodal, kPreviewCells) and the
// picture (four panels, rasterized).
PreviewSurfaces gyroid_preview(int n) {
  const Field phi = gyroid_phase_field(n);
  const Field psi = profile_inverse(phi);
  return preview_surfaces(psi, "G", nodal_level_set("G", 0.4, n).level, 0.9, kPreviewCells);
}

void BM_PreviewSurfaces(benchmark::State& state) {
  const int n = int(state.range(0));
  const Field psi = profile_inverse(gyroid_phase_field(n));
  const double level = nodal_level_set("G", 0.4, n).level;
  for (auto _ : state)
    benchmark::DoNotOptimize(preview_surfaces(psi, "G", level, 0.9, kPreviewCells).scale);
}

void BM_RenderPreview(benchmark::State& state) {
  const PreviewSurfaces s = gyroid_preview(int(state.range(0)));
  for (auto _ : state)
    benchmark::DoNotOptimize(render_preview(s.relaxed, &s.nodal, s.scale, {}).rgb.data());
}

// The 2 x 2 x 2 panel's rasterization alone (the tiles' vertices projected once), tight boxes
// against the reference's.
void BM_DrawTriangles(benchmark::State& state, bool ref) {
  const PreviewSurfaces s = gyroid_preview(128);
  const int size = kPreviewPanel * 2;  // in samples (supersampled twice)
  std::vector<std::vector<ScreenVertex>> tiles;
  for (int t = 0; t < 8; ++t) {
    std::vector<ScreenVertex>& v = tiles.emplace_back(s.relaxed.positions.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto& p = s.relaxed.positions[i];
      const float x = p[0] + (t & 1), y = p[1] + (t >> 1 & 1), z = p[2] + (t >> 2);
      // An oblique orthographic view filling the panel.
      v[i] = {0.27f * size * (x - 0.7f * y + 0.7f), 0.27f * size * (1.4f + 0.3f * x + 0.3f * y - z),
              0.5f * x + 0.5f * y + 0.6f * z, {0.5f, 0.5f, 0.5f}, 0.0f, 0.0f, 1.0f};
    }
  }
  for (auto _ : state) {
    Canvas canvas(kPreviewPanel, kPreviewPanel, 2, {1, 1, 1});
    for (const auto& v : tiles)
      ref ? canvas.draw_triangles_ref(v, s.relaxed.triangles)
          : canvas.draw_triangles(v, s.relaxed.triangles);
    benchmark::DoNotOptimize(canvas.covered());
  }
  state.counters["triangles"] = 8.0 * double(s.relaxed.triangles.size());
}

BENCHMARK(BM_TanhProfileInverse)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LevelSetSurface)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SharpMeasures)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NodalLevelSet)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CmcQuality)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PhaseComponents, fast, false)
    ->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PhaseComponents, ref, true)
    ->Arg(128)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EulerCharacteristic, fast, false)
    ->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EulerCharacteristic, ref, true)
    ->Arg(128)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PreviewSurfaces)->Arg(128)->Arg(256)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RenderPreview)->Arg(128)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DrawTriangles, tight, false)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DrawTriangles, ref, true)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cmcsurf
