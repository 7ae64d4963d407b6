#include "properties/stokes_flow.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/wall_clock.h"
#include "properties/minres.h"
#include "properties/stokes_preconditioner.h"

namespace cmcsurf::properties {

namespace {

// Velocity at voxel centres: the mean of each component's two faces.
void centre_velocity(const StokesOperator& op, const double* x, std::size_t q, double u[3]) {
  const int n = op.n();
  const std::size_t m = op.cells(), i = q % n, j = q / n % n, k = q / (std::size_t(n) * n);
  const std::size_t up[3] = {q - i + (i + 1) % n, q + ((j + 1) % n - j) * n,
                             q + ((k + 1) % n - k) * std::size_t(n) * n};
  for (int c = 0; c < 3; ++c) u[c] = 0.5 * (x[c * m + q] + x[c * m + up[c]]);
}

}  // namespace

FlowPercolation flow_percolation(const StokesOperator& op) {
  const int n = op.n();
  const std::size_t m = op.cells();
  std::vector<int> seen(m, -1);
  std::vector<std::array<int, 3>> pos(m);
  std::vector<std::size_t> queue, members;
  FlowPercolation res;
  double closed = 0.0;
  int comp = 0;
  auto wrapped = [n](const std::array<int, 3>& u) {
    return (std::size_t((u[2] % n + n) % n) * n + (u[1] % n + n) % n) * n + (u[0] % n + n) % n;
  };
  for (std::size_t start = 0; start < m; ++start) {
    if (!op.active_cells()[start] || seen[start] >= 0) continue;
    seen[start] = comp;
    pos[start] = {int(start % n), int(start / n % n), int(start / n / n)};
    queue.assign(1, start);
    members.assign(1, start);
    std::array<bool, 3> wraps{};
    while (!queue.empty()) {
      const std::size_t e = queue.back();
      queue.pop_back();
      for (int c = 0; c < 3; ++c)
        for (int sign : {-1, 1}) {
          std::array<int, 3> u = pos[e];
          u[c] += sign;
          const std::size_t f = wrapped(u);
          // The face between e and f: face e of component c, or face f for the + neighbour.
          if (!op.fluid_face(c, sign < 0 ? e : f)) continue;
          if (seen[f] < 0) {
            seen[f] = comp;
            pos[f] = u;
            queue.push_back(f);
            members.push_back(f);
          } else {
            for (int a = 0; a < 3; ++a)
              if (pos[f][a] != u[a]) wraps[a] = true;  // reached again one period away
          }
        }
    }
    for (int a = 0; a < 3; ++a) res.percolates[a] = res.percolates[a] || wraps[a];
    if (!wraps[0] && !wraps[1] && !wraps[2])
      for (std::size_t e : members) closed += 1.0 - op.solid_fraction()[e];
    ++comp;
  }
  res.closed_pore_fraction = closed / double(m);
  return res;
}

WallShearStats wall_shear_statistics(const StokesOperator& op, const double* x) {
  const int n = op.n();
  const std::size_t m = op.cells();
  auto at = [n](const int v[3]) { return (std::size_t(v[2]) * n + v[1]) * n + v[0]; };
  // Signed du_c/dn at the wall in direction d of fluid face f (0 when there is none), and the
  // wall area of the link (the control volume's section normal to d's axis).
  auto wall_gradient = [&](int c, std::size_t f, int d, double& area) {
    const double th = op.wall_theta(c, f, d);
    if (th == 0.0) return 0.0;
    const int pos[3] = {int(f % n), int(f / n % n), int(f / (std::size_t(n) * n))};
    double len[3] = {0.0, 0.0, 0.0};
    for (int e = 0; e < 6; ++e) {
      const double t = op.wall_theta(c, f, e);
      len[e / 2] += t > 0.0 ? 0.5 * t : 0.5;
    }
    area = len[c] * len[3 - c - d / 2];
    const double u = x[c * m + f];
    if (op.wall_theta(c, f, d ^ 1) != 0.0) return u / th;
    int v[3] = {pos[0], pos[1], pos[2]};  // fluid beyond f: the quadratic through 0, f, N
    v[d / 2] = (v[d / 2] + (d & 1 ? -1 : 1) + n) % n;
    return (u * (th + 1.0) * (th + 1.0) - x[c * m + at(v)] * th * th) / (th * (th + 1.0));
  };
  // One sample per voxel and wall direction: the tangential components from the voxel's two
  // faces of each component (their mean), |tau| from both, the area their links carry.
  std::vector<std::pair<double, double>> samples;  // (|tau|, area)
  for (std::size_t q = 0; q < m; ++q) {
    if (!op.active_cells()[q]) continue;
    const int pos[3] = {int(q % n), int(q / n % n), int(q / (std::size_t(n) * n))};
    for (int d = 0; d < 6; ++d) {
      double tau2 = 0.0, area = 0.0;
      int components = 0;
      for (int c = 0; c < 3; ++c) {
        if (c == d / 2) continue;
        int v[3] = {pos[0], pos[1], pos[2]};
        v[c] = (v[c] + 1) % n;
        double sum = 0.0, a_sum = 0.0;
        int count = 0;
        for (std::size_t f : {q, at(v)}) {
          if (!op.fluid_face(c, f)) continue;
          double a = 0.0;
          const double g = wall_gradient(c, f, d, a);
          if (a == 0.0) continue;
          sum += g;
          a_sum += 0.5 * a;  // a face's control volume is shared by its two voxels
          ++count;
        }
        if (count == 0) continue;
        tau2 += (sum / count) * (sum / count);
        area += a_sum;
        ++components;
      }
      if (components > 0)
        samples.push_back({op.viscosity() * std::sqrt(tau2), area / components});
    }
  }
  WallShearStats st;
  st.histogram.assign(WallShearStats::kHistogramBins, 0.0);
  if (samples.empty()) return st;
  std::sort(samples.begin(), samples.end());
  double total = 0.0, weighted = 0.0;
  for (const auto& s : samples) {
    total += s.second;
    weighted += s.first * s.second;
  }
  st.wall_area = total;
  st.mean = weighted / total;
  st.max = samples.back().first;
  // Area-weighted quantiles: the first sample whose cumulative area reaches the fraction.
  auto quantile = [&](double f) {
    double acc = 0.0;
    for (const auto& s : samples) {
      acc += s.second;
      if (acc >= f * total) return s.first;
    }
    return samples.back().first;
  };
  st.p5 = quantile(0.05);
  st.median = quantile(0.5);
  st.p95 = quantile(0.95);
  for (const auto& s : samples) {
    const int b = st.max > 0.0 ? std::min(WallShearStats::kHistogramBins - 1,
                                          int(s.first / st.max * WallShearStats::kHistogramBins))
                               : 0;
    st.histogram[b] += s.second / total;
  }
  return st;
}

double specific_surface(int n, const std::vector<double>& s) {
  double sum = 0.0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        auto at = [&](int a, int b, int c) {
          return s[(std::size_t((c + n) % n) * n + (b + n) % n) * n + (a + n) % n];
        };
        const double gx = 0.5 * (at(i + 1, j, k) - at(i - 1, j, k)),
                     gy = 0.5 * (at(i, j + 1, k) - at(i, j - 1, k)),
                     gz = 0.5 * (at(i, j, k + 1) - at(i, j, k - 1));
        sum += std::sqrt(gx * gx + gy * gy + gz * gz);
      }
  return sum / (double(n) * n * n);
}

double automatic_sigma(int n, const std::vector<double>& s) {
  double solid = 0.0;
  for (double v : s) solid += v;
  const double porosity = 1.0 - solid / double(s.size());
  const double surface = specific_surface(n, s);
  if (!(surface > 0.0 && porosity > 0.0)) return 1.0;
  const double width = 2.0 * porosity / surface;
  return std::clamp(M_PI * M_PI / (width * width), 1e-4, 1.0);
}

FlowResult compute_permeability(int n, const std::vector<double>& s, const FlowOptions& o,
                                const FlowVisitor& visit) {
  if (n < 2 || s.size() != std::size_t(n) * n * n)
    throw std::invalid_argument("solid fraction: need n >= 2 and n^3 values, got n = " +
                                std::to_string(n) + " and " + std::to_string(s.size()));
  const auto t0 = WallClock::now();
  FlowResult res;
  StokesOperator op(n, s, 1.0, o.theta_min);
  const std::size_t m = op.cells(), size = op.size();
  res.fluid_face_fraction = double(op.fluid_faces()) / double(3 * m);
  // Every face fluid: nothing holds the flow back (k infinite); the caller reports it.
  if (op.fluid_faces() == 3 * m)
    throw std::invalid_argument("pore space: the cell has no solid, so its permeability is "
                                "unbounded");
  const FlowPercolation perc = flow_percolation(op);
  res.percolates = perc.percolates;
  res.closed_pore_fraction = perc.closed_pore_fraction;
  res.sigma = o.sigma > 0.0 ? o.sigma : automatic_sigma(n, s);
  StokesPreconditioner pre(op, res.sigma, o.velocity_preconditioner, o.multigrid);
  Vec x(size), v_prev(size), v(size), z(size), w_prev(size), w(size);
  res.bytes = 6 * size * sizeof(double) + op.bytes() + pre.bytes();
  const CgOptions cg{o.tolerance, 1e-14 * std::sqrt(double(m)), o.max_iterations};
  Matrix3 k{};
  for (int j = 0; j < 3; ++j) {
    // No cluster wraps along j: the net flux of each cluster along j is zero by its mass
    // balance, so k_jj = 0, and k_ij = 0 as k is positive semidefinite: nothing to solve.
    if (!res.percolates[j]) {
      res.load_cases[j].converged = true;
      continue;
    }
    const auto tc = WallClock::now();
    std::fill(v.begin(), v.end(), 0.0);
    for (std::size_t f = 0; f < m; ++f)
      v[j * m + f] = op.face_volume(j, f);  // body force -dP/dx_j = 1 on the control volume
    const CgStats st = minres(
        size, [&](const double* a, double* y) { return op.apply_add(a, y); },
        [&](const double* r, double* y) { pre.apply(r, y); }, x.data(),
        MinresWork{v_prev.data(), v.data(), z.data(), w_prev.data(), w.data()}, cg);
    res.load_cases[j] = {st.iterations, st.relative_residual, st.converged, seconds_since(tc)};
    double umax = 0.0, speed = 0.0, along = 0.0;
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0;
      for (std::size_t f = 0; f < m; ++f) {
        sum += op.face_volume(c, f) * x[c * m + f];  // the flux integral
        umax = std::max(umax, std::abs(x[c * m + f]));
      }
      k[c][j] = sum / double(m);
    }
    for (std::size_t f = 0; f < m; ++f) {
      double u[3];
      centre_velocity(op, x.data(), f, u);
      speed += std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
      along += u[j];
    }
    res.hydraulic_tortuosity[j] = along > 0.0 ? speed / along : 0.0;
    op.divergence(x.data(), z.data());  // z is free after the solve
    double dmax = 0.0;
    for (std::size_t q = 0; q < m; ++q) dmax = std::max(dmax, std::abs(z[q]));
    if (umax > 0.0) res.max_divergence = std::max(res.max_divergence, dmax / umax);
    if (visit) visit(j, op, x.data());
  }
  // The flux along an axis without flow is zero (to the solver's tolerance in the other
  // cases' solutions): exactly zero here.
  for (int a = 0; a < 3; ++a)
    if (!res.percolates[a])
      for (int b = 0; b < 3; ++b) k[a][b] = 0.0;
  double big = 0.0, diff = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      big = std::max(big, std::abs(k[a][b]));
      diff = std::max(diff, std::abs(k[a][b] - k[b][a]));
    }
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) k[a][b] = k[b][a] = 0.5 * (k[a][b] + k[b][a]);
  res.asymmetry = big > 0.0 ? diff / big : 0.0;
  res.permeability = k;
  res.converged = std::all_of(res.load_cases.begin(), res.load_cases.end(),
                              [](const LoadCaseStats& l) { return l.converged; });
  const char* axis_name[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (!res.percolates[a])
      res.warnings.push_back(std::string("pore space does not percolate along ") +
                             axis_name[a] + ": no flow (permeability 0)");
    if (!res.load_cases[a].converged)
      res.warnings.push_back(std::string("flow along ") + axis_name[a] + " not converged (" +
                             std::to_string(res.load_cases[a].iterations) + " iterations)");
  }
  res.seconds = seconds_since(t0);
  return res;
}

}  // namespace cmcsurf::properties
