#include "mesh/morphometry.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>
#include <numeric>

namespace cmcsurf {

namespace {

constexpr double kFar = 1e20;
// Ball radii closer than this (voxels) are merged to the larger: diameters are exact for radii
// up to about 2.5 voxels and at most 2 kRadiusStep short beyond.
constexpr double kRadiusStep = 0.125;

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

namespace {

// Local thickness with `edt` as the distance transform (periodic or of a box); `cap` bounds
// the radii (the distance that stands for "no outside voxel").
std::vector<double> local_thickness_with(
    const std::vector<std::uint8_t>& inside, double cap, double radius_step,
    const std::function<std::vector<double>(const std::vector<std::uint8_t>&)>& edt) {
  const std::vector<double> d2 = edt(inside);
  const std::size_t cells = d2.size();
  // Ball radii: the distinct distances that occur, thinned to steps of at least kRadiusStep.
  std::vector<double> radii;
  for (std::size_t c = 0; c < cells; ++c)
    if (inside[c]) radii.push_back(std::sqrt(std::min(d2[c], cap * cap)));
  std::sort(radii.begin(), radii.end(), std::greater<>());
  radii.erase(std::unique(radii.begin(), radii.end()), radii.end());
  std::vector<double> kept;
  for (double r : radii)
    if (kept.empty() || kept.back() - r >= radius_step) kept.push_back(r);
  // Largest first: x lies in a ball of radius r inside the phase iff it is closer than r to a
  // centre whose own distance is >= r (the opening by that ball).
  std::vector<double> t(cells, 0.0);
  std::vector<std::uint8_t> not_centre(cells);
  std::size_t left = std::count(inside.begin(), inside.end(), std::uint8_t(1));
  for (double r : kept) {
    if (left == 0) break;
    for (std::size_t c = 0; c < cells; ++c) not_centre[c] = !(inside[c] && d2[c] >= r * r - 1e-9);
    const std::vector<double> to_centre = edt(not_centre);
    for (std::size_t c = 0; c < cells; ++c)
      if (inside[c] && t[c] == 0.0 && to_centre[c] < r * r - 1e-9) {
        t[c] = std::max(1.0, 2.0 * r - 1.0);
        --left;
      }
  }
  for (std::size_t c = 0; c < cells; ++c)
    if (inside[c] && t[c] == 0.0) t[c] = 1.0;  // a voxel is at least one voxel thick
  return t;
}

}  // namespace

std::vector<double> local_thickness(const std::vector<std::uint8_t>& inside, int n) {
  return local_thickness_with(inside, n, kRadiusStep, [n](const std::vector<std::uint8_t>& in) {
    return periodic_edt2(in, n);
  });
}

std::vector<double> box_edt2(const std::vector<std::uint8_t>& inside,
                             const std::array<int, 3>& dims, bool outside_beyond) {
  const std::size_t cells = std::size_t(dims[0]) * dims[1] * dims[2];
  std::vector<double> g(cells);
  for (std::size_t id = 0; id < cells; ++id) g[id] = inside[id] ? kFar : 0.0;
  const std::size_t stride[3] = {1, std::size_t(dims[0]), std::size_t(dims[0]) * dims[1]};
  // One axis at a time; a line gets a pad of outside at each end when the box's beyond is
  // outside the phase.
  const int pad = outside_beyond ? 1 : 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const int len = dims[axis], m = len + 2 * pad;
    const long lines = long(dims[a1]) * dims[a2];
#pragma omp parallel
    {
      std::vector<double> f(m), d(m), z(m + 1);
      std::vector<int> v(m);
#pragma omp for schedule(static)
      for (long line = 0; line < lines; ++line) {
        const std::size_t base = (line % dims[a1]) * stride[a1] + (line / dims[a1]) * stride[a2];
        if (pad) f[0] = f[m - 1] = 0.0;
        for (int q = 0; q < len; ++q) f[pad + q] = g[base + q * stride[axis]];
        edt_1d(f, d, v, z);
        for (int q = 0; q < len; ++q) g[base + q * stride[axis]] = std::min(d[pad + q], kFar);
      }
    }
  }
  return g;
}

std::vector<double> box_local_thickness(const std::vector<std::uint8_t>& inside,
                                        const std::array<int, 3>& dims, bool outside_beyond,
                                        double radius_step) {
  const double cap = *std::max_element(dims.begin(), dims.end());
  return local_thickness_with(inside, cap, radius_step, [&](const std::vector<std::uint8_t>& in) {
    return box_edt2(in, dims, outside_beyond);
  });
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
  std::vector<double> values;
  values.reserve(count);
  for (std::size_t c = 0; c < thickness.size(); ++c)
    if (inside[c]) values.push_back(thickness[c] * voxel);
  // Nearest rank: the smallest value with at least q of the voxels at or below it.
  auto percentile = [&](double q) {
    const std::size_t rank = std::min(count - 1, std::size_t(std::ceil(q * count)) - (q > 0));
    std::nth_element(values.begin(), values.begin() + rank, values.end());
    return values[rank];
  };
  s.p5 = percentile(0.05);
  s.p50 = percentile(0.50);
  s.p95 = percentile(0.95);
  const double width = s.max > 0 ? s.max / bins : 1.0;
  s.histogram.assign(bins, 0.0);
  for (int b = 0; b <= bins; ++b) s.histogram_edges.push_back(b * width);
  for (std::size_t c = 0; c < thickness.size(); ++c)
    if (inside[c])
      s.histogram[std::min(bins - 1, int(thickness[c] * voxel / width))] += 1.0 / count;
  return s;
}

nlohmann::json thickness_json(const ThicknessStats& s, const std::string& units) {
  return {{"mean", s.mean},        {"std", s.std},
          {"min", s.min},          {"max", s.max},
          {"p5", s.p5},            {"p50", s.p50},
          {"p95", s.p95},
          {"units", units},        {"volume_fraction", s.fraction},
          {"histogram_edges", s.histogram_edges},
          {"histogram", s.histogram}};
}

std::array<double, 3> throat_diameter(const std::vector<std::uint8_t>& inside, int n) {
  const std::vector<double> d2 = periodic_edt2(inside, n);
  const std::size_t cells = d2.size();
  std::vector<std::size_t> order;
  for (std::size_t c = 0; c < cells; ++c)
    if (inside[c]) order.push_back(c);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return d2[a] > d2[b]; });
  // Union-find over the active centres with each voxel's period offset from its root: two
  // paths to one voxel that arrive in different periods wrap the cell along those axes.
  using Shift = std::array<int, 3>;
  std::vector<std::int64_t> parent(cells, -1);  // -1: not yet active
  std::vector<Shift> shift(cells, Shift{0, 0, 0});
  std::vector<std::array<bool, 3>> wraps(cells, {false, false, false});
  auto find = [&](std::size_t x) {
    // Two passes: to the root summing shifts, then compress the path.
    std::size_t r = x;
    Shift total{0, 0, 0};
    while (std::size_t(parent[r]) != r) {
      for (int c = 0; c < 3; ++c) total[c] += shift[r][c];
      r = std::size_t(parent[r]);
    }
    Shift left = total;
    for (std::size_t y = x; y != r;) {
      const std::size_t up = std::size_t(parent[y]);
      const Shift own = shift[y];
      shift[y] = left;
      parent[y] = std::int64_t(r);
      for (int c = 0; c < 3; ++c) left[c] -= own[c];
      y = up;
    }
    return std::pair{r, total};
  };
  std::array<double, 3> throat{0.0, 0.0, 0.0};
  std::array<bool, 3> found{false, false, false};
  const std::size_t stride[3] = {1, std::size_t(n), std::size_t(n) * n};
  for (std::size_t v : order) {
    parent[v] = std::int64_t(v);
    const int at[3] = {int(v % n), int(v / n % n), int(v / (std::size_t(n) * n))};
    for (int axis = 0; axis < 3; ++axis)
      for (int step : {-1, 1}) {
        const int q = at[axis] + step;
        const int wrapped = q < 0 ? -1 : q >= n ? 1 : 0;  // the neighbour is one period over
        const std::size_t u = v + (std::int64_t((q + n) % n) - at[axis]) * stride[axis];
        if (parent[u] < 0) continue;
        auto [ru, su] = find(u);
        auto [rv, sv] = find(v);
        // u's copy next to v sits at sv + wrapped (along axis) in rv's frame.
        Shift want = sv;
        want[axis] += wrapped;
        if (ru == rv) {
          for (int c = 0; c < 3; ++c)
            if (want[c] != su[c]) wraps[rv][c] = true;
        } else {
          parent[ru] = std::int64_t(rv);
          for (int c = 0; c < 3; ++c) {
            shift[ru][c] = want[c] - su[c];
            wraps[rv][c] = wraps[rv][c] || wraps[ru][c];
          }
        }
        for (int c = 0; c < 3; ++c)
          if (!found[c] && wraps[rv][c]) {
            found[c] = true;
            throat[c] = std::max(1.0, 2.0 * std::sqrt(std::min(d2[v], double(n) * n)) - 1.0);
          }
      }
    if (found[0] && found[1] && found[2]) break;
  }
  return throat;
}

std::array<double, 3> box_throat_diameter(const std::vector<std::uint8_t>& inside,
                                          const std::array<int, 3>& dims) {
  const std::vector<double> d2 = box_edt2(inside, dims, false);
  const std::size_t cells = d2.size();
  const double cap = *std::max_element(dims.begin(), dims.end());
  std::vector<std::size_t> order;
  for (std::size_t c = 0; c < cells; ++c)
    if (inside[c]) order.push_back(c);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return d2[a] > d2[b]; });
  // Union-find over the active centres; each root knows which box faces its set touches
  // (bit 2 axis: the low face, bit 2 axis + 1: the high one).
  std::vector<std::int64_t> parent(cells, -1);  // -1: not yet active
  std::vector<std::uint8_t> faces(cells, 0);
  auto find = [&](std::size_t x) {
    std::size_t r = x;
    while (std::size_t(parent[r]) != r) r = std::size_t(parent[r]);
    while (std::size_t(parent[x]) != r) {
      const std::size_t up = std::size_t(parent[x]);
      parent[x] = std::int64_t(r);
      x = up;
    }
    return r;
  };
  std::array<double, 3> throat{0.0, 0.0, 0.0};
  std::array<bool, 3> found{false, false, false};
  const std::size_t stride[3] = {1, std::size_t(dims[0]), std::size_t(dims[0]) * dims[1]};
  for (std::size_t v : order) {
    parent[v] = std::int64_t(v);
    const int at[3] = {int(v % dims[0]), int(v / dims[0] % dims[1]),
                       int(v / (std::size_t(dims[0]) * dims[1]))};
    std::size_t rv = v;
    for (int axis = 0; axis < 3; ++axis) {
      if (at[axis] == 0) faces[rv] |= std::uint8_t(1u << (2 * axis));
      if (at[axis] == dims[axis] - 1) faces[rv] |= std::uint8_t(2u << (2 * axis));
    }
    for (int axis = 0; axis < 3; ++axis)
      for (int step : {-1, 1}) {
        const int q = at[axis] + step;
        if (q < 0 || q >= dims[axis]) continue;
        const std::size_t u = step < 0 ? v - stride[axis] : v + stride[axis];
        if (parent[u] < 0) continue;
        const std::size_t ru = find(u);
        rv = find(v);
        if (ru == rv) continue;
        parent[ru] = std::int64_t(rv);
        faces[rv] |= faces[ru];
      }
    rv = find(v);
    for (int c = 0; c < 3; ++c)
      if (!found[c] && ((faces[rv] >> (2 * c)) & 3u) == 3u) {
        found[c] = true;
        throat[c] = std::max(1.0, 2.0 * std::sqrt(std::min(d2[v], cap * cap)) - 1.0);
      }
    if (found[0] && found[1] && found[2]) break;
  }
  return throat;
}

}  // namespace cmcsurf
