#include "pipeline/verify.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "measure/measures.h"
#include "multigrid/fas.h"
#include "model/run_options.h"
#include "measure/sharp_volume.h"
#include "surfaces/initial.h"

namespace cmcsurf {

std::string check_verify_grid(int n) {
  if (n > kMaxGrid)  // first: check_coarsenable searches upwards from n
    return fmt::format("got {}; accepted: 8 <= N <= {} (as run --grid), N = m * 2^k with m in "
                       "{{1, 3, 5, 7}} and k >= 2",
                       n, kMaxGrid);
  return check_coarsenable(n);
}

double epsilon_for_cells(int m, int n) {
  return (1.0 / n) * m / (4.0 * std::sqrt(2.0) * std::atanh(0.9));
}

TransitionLayerResult verify_transition_layer(int m, int n, double t_end, std::uint64_t seed,
                                              const ProgressFn& progress) {
  if (const std::string why = check_verify_grid(n); !why.empty())
    throw std::invalid_argument("verify_transition_layer: grid " + why);
  if (m < 1 || !(t_end > 0.0 && t_end <= 1e6))
    throw std::invalid_argument(
        fmt::format("verify_transition_layer: m = {}, t_end = {}; accepted: m >= 1, 0 < t <= 1e6",
                    m, t_end));
  TransitionLayerResult out;
  out.m = m;
  out.n = n;
  out.epsilon = epsilon_for_cells(m, n);
  // 0.5 + 0.01 rand(x_i), rand uniform in [-1, 1], the same in every (y, z) line.
  std::mt19937_64 rng(seed);
  std::vector<double> line(n);
  for (double& v : line) v = 0.5 + 0.01 * (2.0 * (double(rng() >> 11) * 0x1.0p-53) - 1.0);
  Field phi0(n, 1);
  for_each_cell(n, [&](int i, int j, int k) { phi0(i, j, k) = line[i]; });

  RunParams p;
  p.grid = n;
  p.epsilon = out.epsilon;
  p.dt_factor = 0.05 * n;  // dt = 0.05
  p.stop = StopRule::kPhi;
  p.tol = 0.0;  // run to t_end
  p.max_steps = int(std::lround(t_end / 0.05));
  out.run = relax_field(phi0, p, progress);
  if (!out.run.phi.whole())
    throw std::logic_error("verify_transition_layer: the result is a block of a split grid");

  // Along x at j = k = 0: the 0.5 crossings, then for each the 0.1 and 0.9 crossings searched
  // only up to the neighbouring 0.5 crossings (a layer whose neighbours are too close for the
  // profile to reach 0.1 or 0.9 is not a formed interface and is skipped).
  const Field& phi = out.run.phi;
  auto at = [&](int i) { return phi(((i % n) + n) % n, 0, 0); };
  std::vector<double> half;  // positions (in cells) of the 0.5 crossings, increasing
  for (int i = 0; i < n; ++i) {
    const double f0 = at(i), f1 = at(i + 1);
    if ((f0 - 0.5) * (f1 - 0.5) < 0.0) half.push_back(i + (0.5 - f0) / (f1 - f0));
  }
  // First crossing of `level` going from x0 in direction dir, before reaching x_limit.
  auto crossing = [&](double x0, int dir, double x_limit, double level, double* x) {
    for (int a = dir > 0 ? int(std::floor(x0)) : int(std::ceil(x0));
         dir > 0 ? a < x_limit : a > x_limit; a += dir) {
      const int b = a + dir;
      const double fa = at(a), fb = at(b);
      if ((fa - level) * (fb - level) <= 0.0 && fa != fb) {
        *x = a + dir * (level - fa) / (fb - fa);
        return dir > 0 ? *x <= x_limit : *x >= x_limit;
      }
    }
    return false;
  };
  const int count = int(half.size());
  out.crossings = count;
  // Widths between the levels lo and 1 - lo of every formed interface.
  auto widths_between = [&](double lo_level) {
    std::vector<double> widths;
    for (int c = 0; c < count; ++c) {
      const double x = half[c];
      const double prev = c > 0 ? half[c - 1] : half[count - 1] - n;
      const double next = c + 1 < count ? half[c + 1] : half[0] + n;
      const int i = int(std::floor(x));
      const bool rising = at(i + 1) > at(i);
      double lo, hi;
      if (crossing(x, -1, prev, rising ? lo_level : 1 - lo_level, &lo) &&
          crossing(x, 1, next, rising ? 1 - lo_level : lo_level, &hi))
        widths.push_back(hi - lo);
    }
    return widths;
  };
  const std::vector<double> widths = widths_between(0.1);
  out.interfaces = int(widths.size());
  if (!widths.empty()) {
    double sum = 0.0;
    for (double w : widths) sum += w;
    out.mean_width_cells = sum / widths.size();
    out.min_width_cells = *std::min_element(widths.begin(), widths.end());
    out.max_width_cells = *std::max_element(widths.begin(), widths.end());
  }
  const std::vector<double> wide = widths_between(0.05);
  if (!wide.empty()) {
    double sum = 0.0;
    for (double w : wide) sum += w;
    out.mean_width_cells_05 = sum / wide.size();
  }
  return out;
}

double level_radius(const Field& phi, double dx, double dy, double dz) {
  if (!phi.whole()) throw std::logic_error("level_radius on a block of a split grid");
  CMCSURF_CHECK(phi.ghost() >= 1);
  CMCSURF_DCHECK(halo_is_current(phi));
  const int n = phi.n();
  const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
  dx /= len;
  dy /= len;
  dz /= len;
  auto sample = [&](double r) {  // trilinear at (0.5,0.5,0.5) + r d, in cell-centre coordinates
    const double gx = (0.5 + r * dx) * n - 0.5, gy = (0.5 + r * dy) * n - 0.5,
                 gz = (0.5 + r * dz) * n - 0.5;
    const int i = int(std::floor(gx)), j = int(std::floor(gy)), k = int(std::floor(gz));
    const double fx = gx - i, fy = gy - j, fz = gz - k;
    double v = 0.0;
    for (int c = 0; c < 8; ++c) {
      const int a = c & 1, b = (c >> 1) & 1, d = (c >> 2) & 1;
      const double w = (a ? fx : 1 - fx) * (b ? fy : 1 - fy) * (d ? fz : 1 - fz);
      v += w * phi(i + a, j + b, k + d);
    }
    return v;
  };
  const double step = 0.25 / n, r_max = 0.5 - 1.0 / n;
  double r0 = 0.0, v0 = sample(0.0);
  for (double r = step; r <= r_max; r += step) {
    const double v = sample(r);
    if ((v0 - 0.5) * (v - 0.5) <= 0.0 && v != v0) return r0 + step * (0.5 - v0) / (v - v0);
    r0 = r;
    v0 = v;
  }
  return r_max;
}

namespace {

// Sections 4.2 and 4.3: relax phi^0 directly with dt = h until ||dphi|| <= tol.
RunParams direct_relaxation(const char* surface, int n, double epsilon, double tol,
                            int max_steps) {
  RunParams p;
  p.surface = surface;
  p.grid = n;
  p.epsilon = epsilon;
  p.dt_factor = 1.0;
  p.stop = StopRule::kPhi;
  p.tol = tol;
  p.max_steps = max_steps;
  return p;
}

// pi^(1/3) (6 V)^(2/3) / A with V the sharp volume of {phi > 1/2} and A the diffuse area of
// Appendix B.
double sphericity(const Field& phi, double epsilon) {
  return std::cbrt(M_PI) * std::pow(6.0 * sharp_volume_fraction(phi), 2.0 / 3.0) /
         area(phi, epsilon);
}

double axis_to_diagonal_radius(const Field& phi, double* mean_radius) {
  double axis = 0.0, diag = 0.0;
  for (int s = 0; s < 2; ++s) {
    const double d = s ? -1.0 : 1.0;
    axis += level_radius(phi, d, 0, 0) + level_radius(phi, 0, d, 0) + level_radius(phi, 0, 0, d);
  }
  for (int c = 0; c < 8; ++c)
    diag += level_radius(phi, c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
  if (mean_radius) *mean_radius = (axis + diag) / 14.0;
  return (axis / 6.0) / (diag / 8.0);
}

}  // namespace

CubeToSphereResult verify_cube_to_sphere(int n, double epsilon, int max_steps, double tol,
                                         const ProgressFn& progress) {
  if (const std::string why = check_verify_grid(n); !why.empty())
    throw std::invalid_argument("verify_cube_to_sphere: grid " + why);
  const RunParams p = direct_relaxation("cube", n, epsilon, tol, max_steps);
  InitialFieldParams init;
  init.surface = "cube";
  Field cube = make_initial_field(init, n, 2);
  CubeToSphereResult out;
  out.radius_ratio_initial = axis_to_diagonal_radius(cube, nullptr);
  out.run = relax_field(cube, p, progress);
  // The diffuse area measure means nothing on the sharp 0/1 cube: use the geometric value.
  out.sphericity_initial = std::cbrt(M_PI) * std::pow(6.0 * 0.125, 2.0 / 3.0) / 1.5;
  out.run.phi.exchange_halo();
  out.sphericity_final = sphericity(out.run.phi, p.epsilon);
  out.radius_ratio_final = axis_to_diagonal_radius(out.run.phi, &out.mean_radius_final);
  return out;
}

SphereConvergenceRow verify_sphere(int n, double tol, int max_steps, const ProgressFn& progress) {
  RunParams p = direct_relaxation("sphere", n, 0.0073 * 64.0 / n, tol, max_steps);
  p.radius = 0.25;
  RunResult r = run_cmc(p, progress);
  r.phi.exchange_halo();
  SphereConvergenceRow row;
  row.n = n;
  row.epsilon = p.epsilon;
  row.area = area(r.phi, p.epsilon);  // Appendix B, as in Table 1
  row.total_mean_curvature = mean_curvature(r.phi) * row.area;
  row.mean_curvature_mu = mean_curvature_mu(r.phi, p.epsilon);
  row.steps = r.steps;
  row.converged = r.converged;
  row.wall_seconds = r.wall_seconds;
  return row;
}

const std::vector<Table1Reference>& table1_reference() {
  static const std::vector<Table1Reference> paper = {
      {32, 0.42403, 2.25072}, {64, 0.66323, 2.89797}, {128, 0.73742, 3.06842},
      {256, 0.76923, 3.13601}};
  return paper;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// value within rel (a fraction) of expected.
VerifyCheck relative(std::string name, double value, double expected, double rel,
                     std::string basis) {
  const double d = rel * std::abs(expected);
  return {std::move(name), value, expected, expected - d, expected + d, std::move(basis)};
}

VerifyCheck flag(std::string name, bool value, std::string basis) {
  return {std::move(name), value ? 1.0 : 0.0, 1.0, 1.0, 1.0, std::move(basis)};
}

}  // namespace

// Tolerances: docs/verification.md, "Checks and tolerances".
std::vector<VerifyCheck> transition_checks(const TransitionLayerResult& r) {
  const std::string m = fmt::format("m={}", r.m);
  std::vector<VerifyCheck> out;
  out.push_back({m + ": formed interfaces", double(r.interfaces), double(r.crossings), 1.0,
                 kInf, "at least one layer reaches 0.1 and 0.9"});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.push_back(relative(m + ": 0.1->0.9 width (cells)",
                         r.interfaces > 0 ? r.mean_width_cells : nan,
                         r.m * std::atanh(0.8) / std::atanh(0.9), 0.05,
                         "tanh profile; measured within 1.1 %"));
  out.push_back(relative(m + ": 0.05->0.95 width (cells)",
                         r.interfaces > 0 ? r.mean_width_cells_05 : nan, double(r.m), 0.10,
                         "the paper's m cells; measured within 5 %"));
  return out;
}

double cube_sphere_radius() { return std::cbrt(3.0 * 0.125 / (4.0 * M_PI)); }

std::vector<VerifyCheck> cube_checks(const CubeToSphereResult& r, int max_steps) {
  std::vector<VerifyCheck> out;
  out.push_back(flag(fmt::format("relaxed within {} steps", max_steps), r.run.converged,
                     "||dphi|| <= 1e-5 reached"));
  const double r0 = cube_sphere_radius();
  out.push_back({"mean radius of phi=1/2", r.mean_radius_final, r0, 0.8 * r0, r0,
                 "a ball below the cube's volume; measured 0.91"});
  out.push_back({"axis/diagonal radius of phi=1/2", r.radius_ratio_final, 1.0, 0.98, 1.02,
                 "round (cube: 0.577); measured 0.989-0.996"});
  out.push_back({"sphericity", r.sphericity_final, 1.0, 0.97, 1.06,
                 "1 over the diffuse area's low bias"});
  return out;
}

std::vector<VerifyCheck> table1_checks(const std::vector<SphereConvergenceRow>& rows) {
  const auto& paper = table1_reference();
  auto paper_row = [&](int n) -> const Table1Reference* {
    for (const auto& p : paper)
      if (p.n == n) return &p;
    return nullptr;
  };
  std::vector<VerifyCheck> out;
  for (const auto& row : rows) {
    const Table1Reference* ref = paper_row(row.n);
    out.push_back(flag(fmt::format("N={}: relaxed", row.n), row.converged,
                       "||dphi|| <= 1e-5 reached"));
    if (!ref) continue;
    out.push_back(relative(fmt::format("N={}: area", row.n), row.area, ref->area, 0.015,
                           "paper; measured within 0.5 %"));
    out.push_back(relative(fmt::format("N={}: total mean curvature", row.n),
                           row.total_mean_curvature, ref->total_mean_curvature, 0.015,
                           "paper; measured within 0.4 %"));
  }
  // Rates log2(e_h / e_{h/2}) against the exact sphere, beside the paper's.
  auto rate = [](double exact, double coarse, double fine) {
    return std::log2(std::abs(exact - coarse) / std::abs(exact - fine));
  };
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    const Table1Reference* a = paper_row(rows[i].n);
    const Table1Reference* b = paper_row(rows[i + 1].n);
    if (!a || !b || rows[i + 1].n != 2 * rows[i].n) continue;
    const std::string span = fmt::format("{}->{}", rows[i].n, rows[i + 1].n);
    const double pa = rate(M_PI / 4, a->area, b->area);
    const double pt = rate(M_PI, a->total_mean_curvature, b->total_mean_curvature);
    out.push_back({"area rate " + span, rate(M_PI / 4, rows[i].area, rows[i + 1].area), pa,
                   pa - 0.5, pa + 0.5, "paper's rate; measured within 0.05"});
    out.push_back({"total mean curvature rate " + span,
                   rate(M_PI, rows[i].total_mean_curvature, rows[i + 1].total_mean_curvature),
                   pt, pt - 0.5, pt + 0.5, "paper's rate; measured within 0.2"});
  }
  return out;
}

}  // namespace cmcsurf
