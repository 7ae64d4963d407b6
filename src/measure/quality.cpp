#include "measure/quality.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "measure/measures.h"
#include "surfaces/initial.h"

namespace cmcsurf {

namespace {

// Below this 4h|m| the vertex normal is zero, as in measures.cpp.
constexpr double kFlatVertex = 1e-12;

void require_ghost(const Field& phi, int needed, const char* who) {
  if (phi.ghost() < needed)
    throw std::invalid_argument(std::string(who) + ": needs ghost >= " + std::to_string(needed));
}

}  // namespace

// Appendix B at every cell: unit vertex normals from the eight cells around each vertex, then
// kappa = div_d(n) from the eight vertices of the cell.
std::vector<CurvatureSample> local_mean_curvature(Field& phi, double band) {
  require_ghost(phi, 2, "local_mean_curvature");
  phi.exchange_halo();
  const int n = phi.n(), nv = n + 1;
  const double h = phi.h();
  // Vertex (i+1/2, j+1/2, k+1/2) for i, j, k in -1..n-1, stored at (i+1, j+1, k+1).
  auto vidx = [nv](int a, int b, int c) { return (std::size_t(c) * nv + b) * nv + a; };
  std::vector<std::array<double, 3>> normal(std::size_t(nv) * nv * nv);
#pragma omp parallel for schedule(static)
  for (int k = -1; k < n; ++k)
    for (int j = -1; j < n; ++j)
      for (int i = -1; i < n; ++i) {
        double m[3] = {0.0, 0.0, 0.0};
        for (int c = 0; c <= 1; ++c)
          for (int b = 0; b <= 1; ++b)
            for (int a = 0; a <= 1; ++a) {
              const double v = phi(i + a, j + b, k + c);
              m[0] += a ? v : -v;
              m[1] += b ? v : -v;
              m[2] += c ? v : -v;
            }
        const double norm = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        const double inv = norm > kFlatVertex ? 1.0 / norm : 0.0;
        normal[vidx(i + 1, j + 1, k + 1)] = {m[0] * inv, m[1] * inv, m[2] * inv};
      }

  std::vector<std::vector<CurvatureSample>> per_plane(n);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (std::abs(phi(i, j, k) - 0.5) >= band) continue;
        double kappa = 0.0;
        for (int c = 0; c <= 1; ++c)
          for (int b = 0; b <= 1; ++b)
            for (int a = 0; a <= 1; ++a) {
              const auto& nn = normal[vidx(i + a, j + b, k + c)];
              kappa += (a ? nn[0] : -nn[0]) + (b ? nn[1] : -nn[1]) + (c ? nn[2] : -nn[2]);
            }
        kappa /= 4.0 * h;
        // Fourth-order gradient of Appendix B (the area integrand).
        const double gx = (phi(i - 2, j, k) - phi(i + 2, j, k)) + 8.0 * (phi(i + 1, j, k) - phi(i - 1, j, k));
        const double gy = (phi(i, j - 2, k) - phi(i, j + 2, k)) + 8.0 * (phi(i, j + 1, k) - phi(i, j - 1, k));
        const double gz = (phi(i, j, k - 2) - phi(i, j, k + 2)) + 8.0 * (phi(i, j, k + 1) - phi(i, j, k - 1));
        const double w = (gx * gx + gy * gy + gz * gz) / (144.0 * h * h);
        per_plane[k].push_back({-0.5 * kappa, w});
      }
  std::vector<CurvatureSample> out;
  for (auto& p : per_plane) out.insert(out.end(), p.begin(), p.end());
  return out;
}

CurvatureDistribution summarize(const std::vector<CurvatureSample>& samples) {
  CurvatureDistribution d;
  double sw = 0.0, swh = 0.0;
  for (const CurvatureSample& s : samples) {
    sw += s.w;
    swh += s.w * s.h;
  }
  d.weight = sw;
  d.cells = samples.size();
  if (sw <= 0.0) return d;
  d.mean = swh / sw;
  double var = 0.0;
  for (const CurvatureSample& s : samples) var += s.w * (s.h - d.mean) * (s.h - d.mean);
  d.std = std::sqrt(var / sw);
  return d;
}

namespace {

using Point = std::array<double, 3>;

Point lerp(const Point& a, const Point& b, double sa, double sb) {
  const double t = sa / (sa - sb);
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

double cross_norm(const Point& u, const Point& v) {
  const double x = u[1] * v[2] - u[2] * v[1];
  const double y = u[2] * v[0] - u[0] * v[2];
  const double z = u[0] * v[1] - u[1] * v[0];
  return std::sqrt(x * x + y * y + z * z);
}

Point sub(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// Area of {linear interpolant = 0} inside one tetrahedron (vertices p, values s; s > 0 inside).
double tet_area(const std::array<Point, 4>& p, const std::array<double, 4>& s) {
  int in[4], out[4], ni = 0, no = 0;
  for (int v = 0; v < 4; ++v) {
    if (s[v] > 0.0)
      in[ni++] = v;
    else
      out[no++] = v;
  }
  if (ni == 0 || no == 0) return 0.0;
  if (ni == 1 || no == 1) {
    const int apex = ni == 1 ? in[0] : out[0];
    const int* others = ni == 1 ? out : in;
    const Point a = lerp(p[apex], p[others[0]], s[apex], s[others[0]]);
    const Point b = lerp(p[apex], p[others[1]], s[apex], s[others[1]]);
    const Point c = lerp(p[apex], p[others[2]], s[apex], s[others[2]]);
    return 0.5 * cross_norm(sub(b, a), sub(c, a));
  }
  // Planar quad ac, ad, bd, bc: half the cross product of its diagonals.
  const int a = in[0], b = in[1], c = out[0], d = out[1];
  const Point ac = lerp(p[a], p[c], s[a], s[c]), ad = lerp(p[a], p[d], s[a], s[d]);
  const Point bc = lerp(p[b], p[c], s[b], s[c]), bd = lerp(p[b], p[d], s[b], s[d]);
  return 0.5 * cross_norm(sub(bd, ac), sub(bc, ad));
}

// The six tetrahedra of a cube around its diagonal 0-7 (corner v = a + 2b + 4c).
constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                             {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

}  // namespace

double iso_area(Field& phi, double level) {
  require_ghost(phi, 1, "iso_area");
  phi.exchange_halo();
  const int n = phi.n();
  std::array<Point, 8> corner;
  for (int v = 0; v < 8; ++v) corner[v] = {double(v & 1), double((v >> 1) & 1), double((v >> 2) & 1)};
  double sum = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : sum)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        std::array<double, 8> s;
        bool any_in = false, any_out = false;
        for (int v = 0; v < 8; ++v) {
          s[v] = phi(i + (v & 1), j + ((v >> 1) & 1), k + ((v >> 2) & 1)) - level;
          (s[v] > 0.0 ? any_in : any_out) = true;
        }
        if (!any_in || !any_out) continue;
        for (const auto& t : kTets)
          sum += tet_area({corner[t[0]], corner[t[1]], corner[t[2]], corner[t[3]]},
                          {s[t[0]], s[t[1]], s[t[2]], s[t[3]]});
      }
  const double h = phi.h();
  return sum * h * h;
}

NodalPhaseField nodal_phase_field(const std::string& surface, double alpha, int n, double epsilon) {
  if (!is_nodal_surface(surface))
    throw std::invalid_argument("nodal_phase_field: '" + surface + "' is not a nodal surface");
  if (!(alpha > 0.0 && alpha < 1.0))
    throw std::invalid_argument("nodal_phase_field: alpha must be in (0, 1)");
  InitialFieldParams init;
  init.surface = surface;
  Field f = make_initial_field(init, n, 2);  // F + 1/2 at cell centres (step 1)

  // phi = q(d / (2 sqrt2 eps)), d = (F - c)/|grad F| with grad F by central differences of F.
  const double delta = 1e-5;
  const double width = 2.0 * std::numbers::sqrt2 * epsilon;
  const double h = 1.0 / n;
  Field inv_grad(n, 1);  // 1 / (|grad F| width)
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) * h, y = (j + 0.5) * h, z = (k + 0.5) * h;
        const double gx = nodal_value(surface, x + delta, y, z) - nodal_value(surface, x - delta, y, z);
        const double gy = nodal_value(surface, x, y + delta, z) - nodal_value(surface, x, y - delta, z);
        const double gz = nodal_value(surface, x, y, z + delta) - nodal_value(surface, x, y, z - delta);
        const double grad = std::sqrt(gx * gx + gy * gy + gz * gz) / (2.0 * delta);
        inv_grad(i, j, k) = 1.0 / (std::max(grad, 1e-12) * width);
      }
  NodalPhaseField out;
  out.phi = Field(n, 2);
  Field& phi = out.phi;
  auto fill = [&](double c) {
#pragma omp parallel for schedule(static)
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          phi(i, j, k) = 0.5 * (1.0 + std::tanh((f(i, j, k) - c) * inv_grad(i, j, k)));
  };
  // c: a fraction alpha of the cells has F > c, hence phi > 1/2.
  std::vector<double> values;
  values.reserve(f.interior_size());
  for_each_cell(n, [&](int i, int j, int k) { values.push_back(f(i, j, k)); });
  const long total = long(values.size());
  const long above = std::clamp(std::lround(alpha * double(total)), 1L, total - 1);
  std::nth_element(values.begin(), values.begin() + (total - above), values.end());
  const double hi = values[total - above];  // smallest of the `above` largest
  const double lo = *std::max_element(values.begin(), values.begin() + (total - above));
  out.level = 0.5 * (lo + hi);
  fill(out.level);
  phi.exchange_halo();
  return out;
}

std::vector<double> curvature_histogram(const std::vector<CurvatureSample>& samples, double lo,
                                        double hi, int bins) {
  if (bins < 1 || !(hi > lo)) throw std::invalid_argument("curvature_histogram: bad range");
  std::vector<double> hist(bins, 0.0);
  double total = 0.0;
  for (const CurvatureSample& s : samples) {
    const int b = std::clamp(int(std::floor((s.h - lo) / (hi - lo) * bins)), 0, bins - 1);
    hist[b] += s.w;
    total += s.w;
  }
  if (total > 0.0)
    for (double& v : hist) v /= total;
  return hist;
}

CmcQuality compare_with_nodal(Field& relaxed, Field* nodal, double nodal_level, double epsilon) {
  CmcQuality q;
  const std::vector<CurvatureSample> relaxed_samples = local_mean_curvature(relaxed, kQualityBand);
  q.relaxed = summarize(relaxed_samples);
  q.area_iso = iso_area(relaxed);
  std::vector<CurvatureSample> nodal_samples;
  if (nodal) {
    q.has_nodal = true;
    q.nodal_level = nodal_level;
    q.nodal_area = area(*nodal, epsilon);
    q.nodal_area_tanh = q.nodal_area;
    q.nodal_area_iso = iso_area(*nodal);
    q.nodal_mean_curvature = mean_curvature(*nodal);
    q.nodal_volume_fraction = volume_fraction(*nodal);
    nodal_samples = local_mean_curvature(*nodal, kQualityBand);
    q.nodal = summarize(nodal_samples);
  }
  // Common range: mean +- 4 std of both distributions.
  double lo = q.relaxed.mean - 4.0 * q.relaxed.std, hi = q.relaxed.mean + 4.0 * q.relaxed.std;
  if (q.has_nodal) {
    lo = std::min(lo, q.nodal.mean - 4.0 * q.nodal.std);
    hi = std::max(hi, q.nodal.mean + 4.0 * q.nodal.std);
  }
  if (!(hi - lo > 1e-9)) {
    lo -= 1.0;
    hi += 1.0;
  }
  q.edges.resize(kHistogramBins + 1);
  for (int b = 0; b <= kHistogramBins; ++b) q.edges[b] = lo + (hi - lo) * b / kHistogramBins;
  q.relaxed_hist = curvature_histogram(relaxed_samples, lo, hi, kHistogramBins);
  if (q.has_nodal) q.nodal_hist = curvature_histogram(nodal_samples, lo, hi, kHistogramBins);
  return q;
}

}  // namespace cmcsurf
