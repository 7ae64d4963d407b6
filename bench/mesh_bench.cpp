// Google Benchmark of the edge collapser (mesh/edge_collapse.h) on a generated part: CPU time per
// collapse, serial (one slab) and in the slabs its size sets. Rates are per process CPU second,
// so the slabs' threads count; compare with BM_StreamTriad from the same run.
#include <benchmark/benchmark.h>

#include <cstddef>

#include "mesh/edge_collapse.h"
#include "mesh/scaffold_part.h"
#include "surfaces/initial.h"

namespace cmcsurf {
namespace {

// A G sheet, 3 x 3 x 3 cells of the nodal gyroid at 32^3 a cell, undecimated.
const TriMesh& gyroid_sheet() {
  static const TriMesh mesh = [] {
    InitialFieldParams ip;
    ip.surface = "G";
    ScaffoldDesign d;
    d.solid = SolidKind::kSheet;
    d.cell_size = 1.0;
    d.size = {3.0, 3.0, 3.0};
    d.morphometry = false;
    return design_scaffold(make_initial_field(ip, 32, 2), d).mesh;
  }();
  return mesh;
}

// Arg: slabs (1: serial, 0: set by the size). To a quarter of the triangles.
void BM_CollapseEdges(benchmark::State& state) {
  const TriMesh& in = gyroid_sheet();
  CollapseParams p;
  p.target_triangles = in.triangles.size() / 4;
  p.slabs = int(state.range(0));
  std::size_t collapses = 0;
  for (auto _ : state) {
    const TriMesh out = collapse_edges(in, {}, p);
    collapses = (in.triangles.size() - out.triangles.size()) / 2;
    benchmark::DoNotOptimize(out.vertices.data());
  }
  state.counters["triangles"] = double(in.triangles.size());
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(collapses));
}

BENCHMARK(BM_CollapseEdges)
    ->Arg(1)
    ->Arg(0)
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cmcsurf
