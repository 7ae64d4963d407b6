#include "mesh/morphometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace cmcsurf {

namespace {

constexpr double kFar = 1e20;

// Squared distance transform of one line of sampled function f (Felzenszwalb & Huttenlocher
// 2012, Algorithm 1): d(q) = min_p (q - p)^2 + f(p).
void edt_1d(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& v,
            std::vector<double>& z) {
  const int m = int(f.size());
  int k = 0;
  v[0] = 0;
  z[0] = -kFar;
  z[1] = kFar;
  for (int q = 1; q < m; ++q) {
    if (f[q] >= kFar) continue;
    if (f[v[0]] >= kFar) {  // first finite sample
      v[0] = q;
      continue;
    }
    double s;
    for (;;) {
      const int p = v[k];
      s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
      if (s > z[k] || k == 0) break;
      --k;
    }
    if (s <= z[k]) {  // k == 0 and q's parabola wins everywhere
      v[0] = q;
      continue;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kFar;
  }
  if (f[v[0]] >= kFar) {
    std::fill(d.begin(), d.end(), kFar);
    return;
  }
  k = 0;
  for (int q = 0; q < m; ++q) {
    while (z[k + 1] < q) ++k;
    const double dq = q - v[k];
    d[q] = dq * dq + f[v[k]];
  }
}

}  // namespace

std::vector<double> periodic_edt2(const std::vector<std::uint8_t>& inside, int n) {
  const std::size_t cells = std::size_t(n) * n * n;
  std::vector<double> g(cells);
  for (std::size_t id = 0; id < cells; ++id) g[id] = inside[id] ? kFar : 0.0;
  // One axis at a time over lines tripled for the periodic wrap; the middle copy is kept.
  const int m = 3 * n;
  std::vector<double> f(m), d(m), z(m + 1);
  std::vector<int> v(m);
  const std::size_t stride[3] = {1, std::size_t(n), std::size_t(n) * n};
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t s = stride[axis];
    const std::size_t o1 = stride[(axis + 1) % 3], o2 = stride[(axis + 2) % 3];
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        const std::size_t base = a * o1 + b * o2;
        for (int q = 0; q < m; ++q) f[q] = g[base + (q % n) * s];
        edt_1d(f, d, v, z);
        for (int q = 0; q < n; ++q) g[base + q * s] = std::min(d[n + q], kFar);
      }
  }
  return g;
}

std::vector<double> local_thickness(const std::vector<std::uint8_t>& inside, int n) {
  const std::vector<double> r2 = periodic_edt2(inside, n);
  const std::size_t cells = r2.size();
  auto id = [n](int i, int j, int k) {
    auto w = [n](int x) { return ((x % n) + n) % n; };
    return (std::size_t(w(k)) * n + w(j)) * n + w(i);
  };
  // Centres whose ball no neighbour's ball contains (|q - c| + r_c <= r_q).
  std::vector<std::size_t> centres;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t c = id(i, j, k);
        if (!inside[c]) continue;
        const double rc = std::sqrt(r2[c]);
        bool contained = false;
        for (int dk = -1; dk <= 1 && !contained; ++dk)
          for (int dj = -1; dj <= 1 && !contained; ++dj)
            for (int di = -1; di <= 1 && !contained; ++di) {
              if (!(di || dj || dk)) continue;
              const double rq = std::sqrt(r2[id(i + di, j + dj, k + dk)]);
              contained = rq >= rc + std::sqrt(double(di * di + dj * dj + dk * dk));
            }
        if (!contained) centres.push_back(c);
      }
  std::sort(centres.begin(), centres.end(),
            [&](std::size_t a, std::size_t b) { return r2[a] > r2[b]; });
  std::vector<double> t(cells, 0.0);
  for (const std::size_t c : centres) {
    const int i = int(c % n), j = int(c / n % n), k = int(c / (std::size_t(n) * n));
    const double r = std::sqrt(std::min(r2[c], double(n) * n));
    const double diameter = 2.0 * r - 1.0;
    const int b = int(std::ceil(r));
    for (int dk = -b; dk <= b; ++dk)
      for (int dj = -b; dj <= b; ++dj)
        for (int di = -b; di <= b; ++di) {
          if (double(di * di + dj * dj + dk * dk) >= r2[c]) continue;
          double& x = t[id(i + di, j + dj, k + dk)];
          x = std::max(x, diameter);
        }
  }
  for (std::size_t c = 0; c < cells; ++c)
    if (inside[c]) t[c] = std::max(t[c], 1.0);  // a voxel is at least one voxel thick
  return t;
}

ThicknessStats thickness_stats(const std::vector<double>& thickness,
                               const std::vector<std::uint8_t>& inside, double voxel, int bins) {
  ThicknessStats s;
  std::size_t count = 0;
  double sum = 0.0, sum2 = 0.0;
  s.min = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < thickness.size(); ++c) {
    if (!inside[c]) continue;
    const double v = thickness[c] * voxel;
    ++count, sum += v, sum2 += v * v;
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
  }
  s.fraction = double(count) / double(thickness.size());
  if (count == 0) {
    s.min = 0.0;
    return s;
  }
  s.mean = sum / count;
  s.std = std::sqrt(std::max(0.0, sum2 / count - s.mean * s.mean));
  const double width = s.max > 0 ? s.max / bins : 1.0;
  s.histogram.assign(bins, 0.0);
  for (int b = 0; b <= bins; ++b) s.histogram_edges.push_back(b * width);
  for (std::size_t c = 0; c < thickness.size(); ++c)
    if (inside[c]) s.histogram[std::min(bins - 1, int(thickness[c] * voxel / width))] += 1.0 / count;
  return s;
}

nlohmann::json thickness_json(const ThicknessStats& s, const std::string& units) {
  return {{"mean", s.mean},        {"std", s.std},
          {"min", s.min},          {"max", s.max},
          {"units", units},        {"volume_fraction", s.fraction},
          {"histogram_edges", s.histogram_edges},
          {"histogram", s.histogram}};
}

}  // namespace cmcsurf
