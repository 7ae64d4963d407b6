#include "properties/homogenize.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/wall_clock.h"
#include "properties/fft_preconditioner.h"
#include "properties/pcg.h"
#include "properties/voxel_operator.h"

namespace cmcsurf::properties {

namespace {

void check_input(int n, const std::vector<double>& s) {
  if (n < 2 || s.size() != std::size_t(n) * n * n)
    throw std::invalid_argument("solid fraction: need n >= 2 and n^3 values, got n = " +
                                std::to_string(n) + " and " + std::to_string(s.size()));
}

CgOptions cg_options(const SolverOptions& o, std::size_t nodes) {
  // The floor: round-off of a right-hand side that cancels (a homogeneous cell).
  return {o.tolerance, 1e-12 * std::sqrt(double(nodes)), o.max_iterations};
}

// Symmetrised matrix and its relative asymmetry.
template <std::size_t M>
double symmetrise(std::array<std::array<double, M>, M>& a) {
  double big = 0.0, diff = 0.0;
  for (std::size_t i = 0; i < M; ++i)
    for (std::size_t j = 0; j < M; ++j) {
      big = std::max(big, std::abs(a[i][j]));
      diff = std::max(diff, std::abs(a[i][j] - a[j][i]));
    }
  for (std::size_t i = 0; i < M; ++i)
    for (std::size_t j = i + 1; j < M; ++j) a[i][j] = a[j][i] = 0.5 * (a[i][j] + a[j][i]);
  return big > 0.0 ? diff / big : 0.0;
}

// The solver's vectors (x, r, p, q) for m dofs.
struct Workspace {
  explicit Workspace(std::size_t m) : x(m), r(m), p(m), q(m) {}
  Vec x, r, p, q;
  std::size_t bytes() const { return 4 * x.size() * sizeof(double); }
};

// One load case: r = -sum_e s_e K_e u_macro, solve, return the stats.
template <int D>
LoadCaseStats solve_load_case(const VoxelOperator<D>& op, const FftReferencePreconditioner& pre,
                              const typename VoxelOperator<D>::ElementVector& macro_force,
                              const CgOptions& cg, Workspace& w) {
  const auto t0 = WallClock::now();
  std::fill(w.r.begin(), w.r.end(), 0.0);
  op.add_element_vector(macro_force, -1.0, w.r.data());
  const CgStats st = pcg(
      op.size(), [&](const double* p, double* q) { op.apply(p, q); },
      [&](const double* r, double* z) { pre.apply(r, z); }, w.x.data(), w.r.data(), w.p.data(),
      w.q.data(), cg);
  return {st.iterations, st.relative_residual, st.converged, seconds_since(t0)};
}

// K_e times the element's nodal values of an affine field with gradient g (rows: component).
template <int D>
typename VoxelOperator<D>::ElementVector macro_element_force(
    const typename VoxelOperator<D>::ElementMatrix& ke, const std::array<Vector3, D>& g) {
  typename VoxelOperator<D>::ElementVector u{}, f{};
  for (int a = 0; a < 8; ++a)
    for (int c = 0; c < D; ++c)
      for (int d = 0; d < 3; ++d) u[D * a + c] += g[c][d] * double(a >> d & 1);
  for (int r = 0; r < 8 * D; ++r)
    for (int b = 0; b < 8 * D; ++b) f[r] += ke[r][b] * u[b];
  return f;
}

template <int D>
std::vector<float> preconditioner_scaling(const VoxelOperator<D>& op, const SolverOptions& o) {
  std::vector<float> d = op.node_scaling();
  if (!o.diagonal_scaling)
    for (float& v : d) v = v > 0.0f ? 1.0f : 0.0f;
  return d;
}

}  // namespace

ElasticHomogenization homogenize_elasticity(int n, const std::vector<double>& s, double nu,
                                            const SolverOptions& o) {
  check_input(n, s);
  if (!(nu > -1.0 && nu < 0.5))
    throw std::invalid_argument("Poisson ratio of the solid must lie in (-1, 0.5), got " +
                                std::to_string(nu));
  const auto t0 = WallClock::now();
  ElasticHomogenization res;
  VoxelOperator<3> op(n, s, elasticity_element(nu), o.void_below);
  res.removed_solid_fraction = op.removed_solid_fraction();
  const Lame l = lame_of(nu);
  const std::vector<float> scaling = preconditioner_scaling(op, o);
  FftReferencePreconditioner pre(n, 3, l.lambda, l.mu, &scaling);
  Workspace w(op.size());
  res.bytes = w.bytes() + pre.bytes() + op.active_nodes().size() + 4 * scaling.size();
  const Matrix6 cs = isotropic_stiffness(nu);
  const double mean_s = op.mean_solid_fraction();
  const CgOptions cg = cg_options(o, op.nodes());
  Matrix6 c{};
  for (int j = 0; j < 6; ++j) {
    Voigt6 e{};
    e[j] = 1.0;
    const Matrix3 g = strain_tensor(e);
    res.load_cases[j] = solve_load_case(op, pre, macro_element_force<3>(op.element_matrix(), g),
                                        cg, w);
    const auto grad = op.weighted_mean_gradient(w.x.data());  // <s grad u>
    const Voigt6 strain{mean_s * e[0] + grad[0][0],
                        mean_s * e[1] + grad[1][1],
                        mean_s * e[2] + grad[2][2],
                        mean_s * e[3] + grad[1][2] + grad[2][1],
                        mean_s * e[4] + grad[0][2] + grad[2][0],
                        mean_s * e[5] + grad[0][1] + grad[1][0]};
    for (int i = 0; i < 6; ++i)
      for (int k = 0; k < 6; ++k) c[i][j] += cs[i][k] * strain[k];  // <sigma> = C_s <s eps>
  }
  res.asymmetry = symmetrise(c);
  res.stiffness_voigt = c;
  res.converged = std::all_of(res.load_cases.begin(), res.load_cases.end(),
                              [](const LoadCaseStats& l) { return l.converged; });
  res.seconds = seconds_since(t0);
  return res;
}

ConductivityHomogenization homogenize_conductivity(int n, const std::vector<double>& s,
                                                   const SolverOptions& o) {
  check_input(n, s);
  const auto t0 = WallClock::now();
  ConductivityHomogenization res;
  VoxelOperator<1> op(n, s, conductivity_element(), o.void_below);
  res.removed_solid_fraction = op.removed_solid_fraction();
  const std::vector<float> scaling = preconditioner_scaling(op, o);
  FftReferencePreconditioner pre(n, 1, 0.0, 0.0, &scaling);
  Workspace w(op.size());
  res.bytes = w.bytes() + pre.bytes() + op.active_nodes().size() + 4 * scaling.size();
  const double mean_s = op.mean_solid_fraction();
  const CgOptions cg = cg_options(o, op.nodes());
  Matrix3 k{};
  for (int j = 0; j < 3; ++j) {
    std::array<Vector3, 1> g{};
    g[0][j] = 1.0;
    res.load_cases[j] = solve_load_case(op, pre, macro_element_force<1>(op.element_matrix(), g),
                                        cg, w);
    const auto grad = op.weighted_mean_gradient(w.x.data());
    for (int i = 0; i < 3; ++i) k[i][j] = (i == j ? mean_s : 0.0) + grad[0][i];
  }
  res.asymmetry = symmetrise(k);
  res.conductivity = k;
  res.converged = std::all_of(res.load_cases.begin(), res.load_cases.end(),
                              [](const LoadCaseStats& l) { return l.converged; });
  res.seconds = seconds_since(t0);
  return res;
}

}  // namespace cmcsurf::properties
