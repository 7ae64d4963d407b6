// Google Benchmark kernels of the properties solvers (docs/properties.md): the voxel stencil,
// the FFT preconditioner and a full homogenisation, on the nodal gyroid network at porosity 0.7;
// the Stokes stencil, its preconditioner and the permeability tensor.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "properties/fft_preconditioner.h"
#include "properties/homogenize.h"
#include "properties/solid_fraction.h"
#include "properties/stokes_flow.h"
#include "properties/stokes_preconditioner.h"
#include "properties/voxel_element.h"
#include "properties/voxel_operator.h"

namespace cmcsurf::properties {
namespace {

std::vector<double> gyroid(int n) {
  return nodal_gyroid_solid_fraction(n, GyroidSolid::network, 0.7);
}  // porosity 0.7

Vec random_vec(std::size_t m) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec v(m);
  for (double& x : v) x = u(rng);
  return v;
}

// y = K x; counts cells (voxels) per second.
template <int D>
void BM_VoxelStencil(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto s = gyroid(n);
  typename VoxelOperator<D>::ElementMatrix ke;
  if constexpr (D == 1)
    ke = conductivity_element();
  else
    ke = elasticity_element(0.3);
  VoxelOperator<D> op(n, s, ke);
  const Vec x = random_vec(op.size());
  Vec y(op.size());
  for (auto _ : state) {
    op.apply(x.data(), y.data());
    benchmark::DoNotOptimize(y.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(op.nodes()));
}
BENCHMARK(BM_VoxelStencil<1>)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VoxelStencil<3>)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

// z = D M^-1 D r (forward and backward FFT of D dofs per node).
template <int D>
void BM_FftPreconditioner(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto s = gyroid(n);
  VoxelOperator<D> op(n, s, typename VoxelOperator<D>::ElementMatrix{});
  const std::vector<float> scaling = op.node_scaling();
  const Lame l = lame_of(0.3);
  FftReferencePreconditioner pre(n, D, l.lambda, l.mu, &scaling);
  const Vec r = random_vec(op.size());
  Vec z(op.size());
  for (auto _ : state) {
    pre.apply(r.data(), z.data());
    benchmark::DoNotOptimize(z.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(op.nodes()));
}
BENCHMARK(BM_FftPreconditioner<1>)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FftPreconditioner<3>)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

// All six elastic load cases on the gyroid network (kind 0) or sheet (kind 1); counters: the
// largest CG iteration count of a case, C11, C12, C44 (docs/properties.md's tables; 128^3
// takes minutes: --benchmark_filter='Homogenize.*/128').
void BM_HomogenizeElasticity(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto s = nodal_gyroid_solid_fraction(
      n, state.range(1) ? GyroidSolid::sheet : GyroidSolid::network, 0.7);
  ElasticHomogenization r;
  for (auto _ : state) {
    r = homogenize_elasticity(n, s, 0.3);
    benchmark::DoNotOptimize(r.stiffness_voigt.data());
  }
  int most = 0;
  for (const auto& c : r.load_cases) most = std::max(most, c.iterations);
  state.counters["cg_iterations"] = most;
  state.counters["C11"] = r.stiffness_voigt[0][0];
  state.counters["C12"] = r.stiffness_voigt[0][1];
  state.counters["C44"] = r.stiffness_voigt[3][3];
  state.counters["bytes_per_cell"] = double(r.bytes) / (double(n) * n * n);
}
BENCHMARK(BM_HomogenizeElasticity)
    ->ArgsProduct({{32, 64, 128}, {0, 1}})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

// The three conduction load cases of the solid (kind 0 network, 1 sheet).
void BM_HomogenizeConductivity(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto s = nodal_gyroid_solid_fraction(
      n, state.range(1) ? GyroidSolid::sheet : GyroidSolid::network, 0.7);
  ConductivityHomogenization r;
  for (auto _ : state) {
    r = homogenize_conductivity(n, s);
    benchmark::DoNotOptimize(r.conductivity.data());
  }
  int most = 0;
  for (const auto& c : r.load_cases) most = std::max(most, c.iterations);
  state.counters["cg_iterations"] = most;
  state.counters["k11"] = r.conductivity[0][0];
}
BENCHMARK(BM_HomogenizeConductivity)
    ->ArgsProduct({{32, 64, 128}, {0, 1}})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

// y = K x of the Stokes system (velocity and pressure); counts cells per second.
void BM_StokesStencil(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto s = gyroid(n);
  const StokesOperator op(n, s);
  const Vec x = random_vec(op.size());
  Vec y(op.size());
  for (auto _ : state) {
    op.apply(x.data(), y.data());
    benchmark::DoNotOptimize(y.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(op.cells()));
}
BENCHMARK(BM_StokesStencil)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

// The block preconditioner: three FFT Laplacian solves and the pressure scaling.
void BM_StokesPreconditioner(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto s = gyroid(n);
  const StokesOperator op(n, s);
  const StokesPreconditioner pre(op, automatic_sigma(n, s));
  const Vec r = random_vec(op.size());
  Vec z(op.size());
  for (auto _ : state) {
    pre.apply(r.data(), z.data());
    benchmark::DoNotOptimize(z.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(op.cells()));
}
BENCHMARK(BM_StokesPreconditioner)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

// The permeability tensor (three load cases) of the gyroid network at porosity 0.7 with the
// multigrid (second argument 0) or the FFT (1) velocity block; wall time (threads from
// OMP_NUM_THREADS); counters: k_xx in cell-size^2, the largest MINRES iteration count, bytes
// per cell (128^3 takes minutes: --benchmark_filter='Permeability/128').
void BM_Permeability(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto s = gyroid(n);
  FlowOptions o;
  o.velocity_preconditioner =
      state.range(1) == 0 ? VelocityPreconditioner::multigrid : VelocityPreconditioner::fft;
  FlowResult r;
  for (auto _ : state) {
    r = compute_permeability(n, s, o);
    benchmark::DoNotOptimize(r.permeability.data());
  }
  int most = 0;
  for (const auto& c : r.load_cases) most = std::max(most, c.iterations);
  state.counters["minres_iterations"] = most;
  state.counters["k11_cell2"] = r.permeability[0][0] / (double(n) * n);
  state.counters["bytes_per_cell"] = double(r.bytes) / (double(n) * n * n);
}
BENCHMARK(BM_Permeability)
    ->ArgsProduct({{32, 64, 128}, {0, 1}})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

// The multigrid's cycle: arguments n, Jacobi sweeps, coarse visits (1 V, 2 W); wall time and
// the counters of BM_Permeability.
void BM_PermeabilityMultigridCycle(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto s = gyroid(n);
  FlowOptions o;
  o.multigrid.sweeps = int(state.range(1));
  o.multigrid.cycles = int(state.range(2));
  FlowResult r;
  for (auto _ : state) {
    r = compute_permeability(n, s, o);
    benchmark::DoNotOptimize(r.permeability.data());
  }
  int most = 0;
  for (const auto& c : r.load_cases) most = std::max(most, c.iterations);
  state.counters["minres_iterations"] = most;
  state.counters["k11_cell2"] = r.permeability[0][0] / (double(n) * n);
}
BENCHMARK(BM_PermeabilityMultigridCycle)
    ->ArgsProduct({{32, 64}, {1, 2, 3}, {1, 2}})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

// One preconditioner application with the multigrid velocity block (three W-cycles).
void BM_StokesMultigrid(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto s = gyroid(n);
  const StokesOperator op(n, s);
  const StokesPreconditioner pre(op, automatic_sigma(n, s), VelocityPreconditioner::multigrid);
  const Vec r = random_vec(op.size());
  Vec z(op.size());
  for (auto _ : state) {
    pre.apply(r.data(), z.data());
    benchmark::DoNotOptimize(z.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(op.cells()));
}
BENCHMARK(BM_StokesMultigrid)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

// Exact flows (docs/properties.md, "Validation"): kind 0 the slit y in [0.2718 n, 0.7281 n]
// (k = phi w^2 / 12), kind 1 the tube of radius 0.3 n around (n/2 + 0.1, n/2 - 0.23) along z
// (k = phi R^2 / 8, fractions from 64 x 64 subsamples); staircase 1 rounds every fraction to 0
// or 1. Counter: k / exact - 1.
void BM_PermeabilityExactFlows(benchmark::State& state) {
  const int n = int(state.range(0)), kind = int(state.range(1));
  std::vector<double> s(std::size_t(n) * n * n);
  double exact = 0.0;
  int axis = 0;
  if (kind == 0) {
    const double a = 0.2718 * n, w = 0.4563 * n;
    for (std::size_t q = 0; q < s.size(); ++q) {
      const double j = double(q / n % n);
      s[q] = 1.0 - std::max(0.0, std::min(j + 1.0, a + w) - std::max(j, a));
    }
    exact = (w / n) * w * w / 12.0;
  } else {
    const double r = 0.3 * n, cx = 0.5 * n + 0.1, cy = 0.5 * n - 0.23;
    const int sub = 64;
    for (std::size_t q = 0; q < s.size(); ++q) {
      const int i = int(q % n), j = int(q / n % n);
      int inside = 0;
      for (int b = 0; b < sub; ++b)
        for (int a = 0; a < sub; ++a) {
          const double x = i + (a + 0.5) / sub - cx, y = j + (b + 0.5) / sub - cy;
          inside += x * x + y * y < r * r;
        }
      s[q] = 1.0 - double(inside) / (sub * sub);
    }
    exact = M_PI * r * r / (double(n) * n) * r * r / 8.0;
    axis = 2;
  }
  if (state.range(2))
    for (double& v : s) v = v >= 0.5 ? 1.0 : 0.0;
  FlowResult r;
  for (auto _ : state) {
    r = compute_permeability(n, s);
    benchmark::DoNotOptimize(r.permeability.data());
  }
  state.counters["k_over_exact_minus_1"] = r.permeability[axis][axis] / exact - 1.0;
}
BENCHMARK(BM_PermeabilityExactFlows)
    ->ArgsProduct({{32, 64}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace cmcsurf::properties
