#include "properties/cell_properties.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/wall_clock.h"
#include "properties/solid_fraction.h"

namespace cmcsurf::properties {

namespace {

// (C + delta I)^-1 by Gauss-Jordan with partial pivoting; the smallest pivot relative to
// max |C| through min_pivot. delta (1e-10 max |C|) keeps a singular C (a solid that does not
// percolate) invertible, so that its axes come out with E ~ 0 and the others right.
Matrix6 regularised_inverse(const Matrix6& c, double* min_pivot) {
  double big = 0.0;
  for (const auto& row : c)
    for (double v : row) big = std::max(big, std::abs(v));
  std::array<std::array<double, 12>, 6> a{};
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) a[i][j] = c[i][j] + (i == j ? 1e-10 * big : 0.0);
    a[i][6 + i] = 1.0;
  }
  *min_pivot = std::numeric_limits<double>::infinity();
  for (int col = 0; col < 6; ++col) {
    int p = col;
    for (int r = col + 1; r < 6; ++r)
      if (std::abs(a[r][col]) > std::abs(a[p][col])) p = r;
    std::swap(a[p], a[col]);
    const double piv = a[col][col];
    *min_pivot = std::min(*min_pivot, big > 0.0 ? std::abs(piv) / big : 0.0);
    if (piv == 0.0) return Matrix6{};
    for (double& v : a[col]) v /= piv;
    for (int r = 0; r < 6; ++r)
      if (r != col) {
        const double f = a[r][col];
        for (int j = 0; j < 12; ++j) a[r][j] -= f * a[col][j];
      }
  }
  Matrix6 s{};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) s[i][j] = a[i][6 + j];
  return s;
}

Vector3 normalised(const Vector3& d) {
  const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return {d[0] / l, d[1] / l, d[2] / l};
}

// Extremum of E(d) over the sphere: a Fibonacci lattice of 4000 directions plus the axes and
// the face and body diagonals, then a pattern search around the best (sign: +1 max, -1 min).
Vector3 extreme_direction(const Matrix6& s, double sign) {
  auto score = [&](const Vector3& d) { return sign * directional_youngs_modulus(s, d); };
  std::vector<Vector3> cand = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1},
                               {0, 1, 1}, {1, -1, 0}, {1, 0, -1}, {0, 1, -1}, {1, 1, 1},
                               {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};
  const int m = 4000;
  for (int q = 0; q < m; ++q) {  // upper hemisphere: E(d) = E(-d)
    const double z = (q + 0.5) / m, r = std::sqrt(1.0 - z * z);
    const double a = q * M_PI * (3.0 - std::sqrt(5.0));
    cand.push_back({r * std::cos(a), r * std::sin(a), z});
  }
  Vector3 best = normalised(cand[0]);
  for (const auto& c : cand)
    if (score(normalised(c)) > score(best)) best = normalised(c);
  for (double step = 0.05; step > 1e-7; step *= 0.5) {
    bool moved = true;
    while (moved) {
      moved = false;
      for (int axis = 0; axis < 3; ++axis)
        for (double sg : {-1.0, 1.0}) {
          Vector3 t = best;
          t[axis] += sg * step;
          t = normalised(t);
          if (score(t) > score(best)) {
            best = t;
            moved = true;
          }
        }
    }
  }
  return best;
}

void append_axes_warning(std::vector<std::string>& w, const std::array<bool, 3>& perc,
                         const std::string& what) {
  std::string axes;
  for (int a = 0; a < 3; ++a)
    if (!perc[a]) axes += std::string(axes.empty() ? "" : ", ") + "xyz"[a];
  if (!axes.empty()) w.push_back(what + " does not percolate along " + axes);
}

void append_convergence_warning(std::vector<std::string>& w, const LoadCaseStats* cases,
                                int count, const std::string& what) {
  for (int j = 0; j < count; ++j)
    if (!cases[j].converged)
      w.push_back(what + " load case " + std::to_string(j + 1) + " not converged after " +
                  std::to_string(cases[j].iterations) + " iterations (relative residual " +
                  std::to_string(cases[j].relative_residual) + ")");
}

}  // namespace

double directional_youngs_modulus(const Matrix6& s, const Vector3& d) {
  const Voigt6 v{d[0] * d[0], d[1] * d[1], d[2] * d[2], d[1] * d[2], d[0] * d[2], d[0] * d[1]};
  double q = 0.0;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) q += v[i] * s[i][j] * v[j];
  return q > 0.0 ? 1.0 / q : 0.0;
}

ElasticConstants elastic_constants(const Matrix6& c) {
  ElasticConstants e;
  double min_pivot = 0.0;
  e.compliance_voigt = regularised_inverse(c, &min_pivot);
  e.invertible = min_pivot > 1e-6;
  const Matrix6& s = e.compliance_voigt;
  for (int i = 0; i < 3; ++i) {
    e.youngs_modulus[i] = s[i][i] > 0.0 ? 1.0 / s[i][i] : 0.0;
    e.shear_modulus[i] = s[i + 3][i + 3] > 0.0 ? 1.0 / s[i + 3][i + 3] : 0.0;
    for (int j = 0; j < 3; ++j)
      e.poisson_ratio[i][j] = i == j || s[i][i] == 0.0 ? 0.0 : -s[j][i] / s[i][i];
  }
  double diag = 0.0, off = 0.0, shear = 0.0;
  for (int i = 0; i < 3; ++i) {
    diag += c[i][i];
    off += c[i][(i + 1) % 3];
    shear += c[i + 3][i + 3];
  }
  e.bulk_modulus = (diag + 2.0 * off) / 9.0;
  e.shear_modulus_mean = (diag - off + 3.0 * shear) / 15.0;
  const double k = e.bulk_modulus, g = e.shear_modulus_mean;
  e.youngs_modulus_mean = 3.0 * k + g > 0.0 ? 9.0 * k * g / (3.0 * k + g) : 0.0;
  const double c11 = diag / 3.0, c12 = off / 3.0, c44 = shear / 3.0;  // cubic means
  e.zener_ratio = c11 != c12 ? 2.0 * c44 / (c11 - c12) : 0.0;
  e.direction_min = extreme_direction(s, -1.0);
  e.direction_max = extreme_direction(s, 1.0);
  e.youngs_modulus_min = directional_youngs_modulus(s, e.direction_min);
  e.youngs_modulus_max = directional_youngs_modulus(s, e.direction_max);
  return e;
}

HashinShtrikman hashin_shtrikman_upper(double f, double nu) {
  const double ks = 1.0 / (3.0 * (1.0 - 2.0 * nu)), gs = 1.0 / (2.0 * (1.0 + nu));
  HashinShtrikman b{};
  b.bulk_modulus = 4.0 * ks * gs * f / (3.0 * ks * (1.0 - f) + 4.0 * gs);
  // G_s + f_void / (-1 / G_s + 6 f (K_s + 2 G_s) / (5 G_s (3 K_s + 4 G_s)))
  const double denom = -1.0 / gs + 6.0 * f * (ks + 2.0 * gs) / (5.0 * gs * (3.0 * ks + 4.0 * gs));
  b.shear_modulus = f >= 1.0 ? gs : gs + (1.0 - f) / denom;
  const double k = b.bulk_modulus, g = b.shear_modulus;
  b.youngs_modulus = 3.0 * k + g > 0.0 ? 9.0 * k * g / (3.0 * k + g) : 0.0;
  b.conductivity = 2.0 * f / (3.0 - f);
  return b;
}

std::array<bool, 3> percolating_axes(int n, const std::vector<double>& s, double void_below) {
  auto solid = [&](std::size_t e) { return s[e] > 0.0 && s[e] >= void_below; };
  const std::size_t cells = std::size_t(n) * n * n;
  std::vector<int> seen(cells, -1);                // component id
  std::vector<std::array<int, 3>> pos(cells);      // unwrapped position in the component
  std::array<bool, 3> perc{};
  std::vector<std::size_t> queue;
  int comp = 0;
  for (std::size_t start = 0; start < cells; ++start) {
    if (!solid(start) || seen[start] >= 0) continue;
    seen[start] = comp;
    pos[start] = {int(start % n), int(start / n % n), int(start / n / n)};
    queue.assign(1, start);
    while (!queue.empty()) {
      const std::size_t e = queue.back();
      queue.pop_back();
      const auto p = pos[e];
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const std::array<int, 3> u{p[0] + dx, p[1] + dy, p[2] + dz};
            const std::size_t f = (std::size_t((u[2] % n + n) % n) * n + (u[1] % n + n) % n) * n +
                                  (u[0] % n + n) % n;
            if (!solid(f)) continue;
            if (seen[f] < 0) {
              seen[f] = comp;
              pos[f] = u;
              queue.push_back(f);
            } else {
              for (int a = 0; a < 3; ++a)
                if (pos[f][a] != u[a]) perc[a] = true;  // reached again one period away
            }
          }
    }
    ++comp;
  }
  return perc;
}

CellProperties compute_cell_properties(int n, const std::vector<double>& s,
                                       const CellPropertiesOptions& o) {
  const auto t0 = WallClock::now();
  CellProperties p;
  p.n = n;
  p.poisson_ratio_solid = o.poisson_ratio;
  if (n < 2 || s.size() != std::size_t(n) * n * n)
    throw std::invalid_argument("cell properties: need n >= 2 and n^3 solid fractions");
  double sum = 0.0;
  for (double v : s) sum += v;
  p.relative_density = sum / double(s.size());
  p.porosity = 1.0 - p.relative_density;
  p.bound_solid = hashin_shtrikman_upper(p.relative_density, o.poisson_ratio);
  p.bound_conductivity_pore = hashin_shtrikman_upper(p.porosity, o.poisson_ratio).conductivity;
  p.solid_percolates = percolating_axes(n, s, o.solver.void_below);
  append_axes_warning(p.warnings, p.solid_percolates, "solid");
  if (o.elasticity) {
    p.elastic = homogenize_elasticity(n, s, o.poisson_ratio, o.solver);
    p.constants = elastic_constants(p.elastic.stiffness_voigt);
    p.bulk_fraction_of_bound = p.constants.bulk_modulus / p.bound_solid.bulk_modulus;
    p.shear_fraction_of_bound = p.constants.shear_modulus_mean / p.bound_solid.shear_modulus;
    p.youngs_fraction_of_bound = p.constants.youngs_modulus_mean / p.bound_solid.youngs_modulus;
    append_convergence_warning(p.warnings, p.elastic.load_cases.data(), 6, "elasticity");
  }
  if (o.conductivity) {
    p.solid_conduction = homogenize_conductivity(n, s, o.solver);
    const Matrix3& ks = p.solid_conduction.conductivity;
    p.conductivity_solid_fraction_of_bound =
        (ks[0][0] + ks[1][1] + ks[2][2]) / 3.0 / p.bound_solid.conductivity;
    append_convergence_warning(p.warnings, p.solid_conduction.load_cases.data(), 3,
                               "solid conduction");
    std::vector<double> pore(s.size());
    for (std::size_t e = 0; e < s.size(); ++e) pore[e] = 1.0 - s[e];
    p.pore_percolates = percolating_axes(n, pore, o.solver.void_below);
    append_axes_warning(p.warnings, p.pore_percolates, "pore space");
    p.pore_conduction = homogenize_conductivity(n, pore, o.solver);
    const Matrix3& kp = p.pore_conduction.conductivity;
    for (int a = 0; a < 3; ++a) {
      p.formation_factor[a] =
          kp[a][a] > 0.0 ? 1.0 / kp[a][a] : std::numeric_limits<double>::infinity();
      p.tortuosity_pore[a] = p.porosity * p.formation_factor[a];
    }
    p.conductivity_pore_fraction_of_bound =
        p.bound_conductivity_pore > 0.0
            ? (kp[0][0] + kp[1][1] + kp[2][2]) / 3.0 / p.bound_conductivity_pore
            : 0.0;
    append_convergence_warning(p.warnings, p.pore_conduction.load_cases.data(), 3,
                               "pore conduction");
  }
  if (o.flow) {
    p.specific_surface = specific_surface(n, s);
    try {
      p.flow = compute_permeability(n, s, o.flow_solver,
                                    [&](int axis, const StokesOperator& op, const double* x) {
                                      p.wall_shear_axes[axis] = wall_shear_statistics(op, x);
                                    });
      p.wall_shear = p.wall_shear_axes[2];
    } catch (const std::invalid_argument& e) {  // no solid face: nothing holds the flow back
      p.warnings.push_back(std::string("flow not computed: ") + e.what());
    }
    const Matrix3& k = p.flow.permeability;
    const double k_mean = (k[0][0] + k[1][1] + k[2][2]) / 3.0;
    if (k_mean > 0.0 && p.specific_surface > 0.0)
      p.kozeny_carman_constant =
          std::pow(p.porosity, 3) / (k_mean * p.specific_surface * p.specific_surface);
    p.warnings.insert(p.warnings.end(), p.flow.warnings.begin(), p.flow.warnings.end());
  }
  p.seconds = seconds_since(t0);
  return p;
}

double richardson_limit(double fine, double coarse, double order) {
  return fine + (fine - coarse) / (std::pow(2.0, order) - 1.0);
}

GridCheck grid_check(int n, const std::vector<double>& s, const CellPropertiesOptions& o) {
  return {compute_cell_properties(n, s, o),
          compute_cell_properties(n / 2, restrict_solid_fraction(n, s), o)};
}

}  // namespace cmcsurf::properties
