#include "render/draw_surface.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "grid/check.h"
#include "measure/sharp_surface.h"
#include "mesh/marching_tets.h"

namespace cmcsurf {

int draw_stride(int n, int max_cells) {
  for (int s = 1; s <= n; ++s)
    if (n % s == 0 && n / s <= max_cells) return s;
  return n;
}

namespace {

// H and -grad psi at cell (i, j, k) (periodic indices), from the full-resolution psi.
struct CellValues {
  double h;
  double g[3];
};

CellValues cell_values(const Field& psi, int i, int j, int k) {
  const int n = psi.n();
  i = (i % n + n) % n;
  j = (j % n + n) % n;
  k = (k % n + n) % n;
  const double* p = &psi(i, j, k);
  const std::ptrdiff_t sy = psi.stride_y(), sz = psi.stride_z();
  return {level_set_mean_curvature(p, sy, sz, double(n)),
          {-0.5 * (p[1] - p[-1]), -0.5 * (p[sy] - p[-sy]), -0.5 * (p[sz] - p[-sz])}};
}

}  // namespace

namespace {

// H and -grad psi interpolated trilinearly from the eight cell centres around x (unit-cell
// coordinates), read through `at` (global cell indices in [0, n]; the caller wraps or maps).
template <class At>
void vertex_values(const Vec3& x, double h, At&& at, double out[4]) {
  double u[3];
  int c[3];
  for (int a = 0; a < 3; ++a) {
    const double t = x[a] / h - 0.5;
    c[a] = int(std::floor(t));
    u[a] = t - c[a];
  }
  double hv = 0.0, g[3] = {0, 0, 0};
  for (int corner = 0; corner < 8; ++corner) {
    const int dx = corner & 1, dy = corner >> 1 & 1, dz = corner >> 2 & 1;
    const double w = (dx ? u[0] : 1 - u[0]) * (dy ? u[1] : 1 - u[1]) * (dz ? u[2] : 1 - u[2]);
    const CellValues cv = at(c[0] + dx, c[1] + dy, c[2] + dz);
    hv += w * cv.h;
    for (int a = 0; a < 3; ++a) g[a] += w * cv.g[a];
  }
  out[0] = hv;
  out[1] = g[0];
  out[2] = g[1];
  out[3] = g[2];
}

// The cell whose centre is the low corner of x's interpolation cube (global, wrapped).
std::array<int, 3> base_cell(const Vec3& x, double h, int n) {
  std::array<int, 3> c;
  for (int a = 0; a < 3; ++a) c[a] = ((int(std::floor(x[a] / h - 0.5)) % n) + n) % n;
  return c;
}

CellValues block_cell_values(const Field& psi, int i, int j, int k) {
  const double* p = &psi(i, j, k);
  const std::ptrdiff_t sy = psi.stride_y(), sz = psi.stride_z();
  return {level_set_mean_curvature(p, sy, sz, double(psi.n())),
          {-0.5 * (p[1] - p[-1]), -0.5 * (p[sy] - p[-sy]), -0.5 * (p[sz] - p[-sz])}};
}

}  // namespace

DrawSurface draw_surface(const Field& psi, int max_cells) {
  require_ghost(psi, 2, "draw_surface");
  CMCSURF_DCHECK(halo_is_current(psi));  // the curvature stencil reads the ghosts
  if (max_cells < 2) throw std::invalid_argument("draw_surface: max_cells must be >= 2");
  const Decomposition* d = psi.decomposition();
  const bool split = d && d->distributed();
  const int n = psi.n();
  const int s = draw_stride(n, max_cells);
  const int m = n / s;
  const double h = psi.h();
  // The drawing lattice's m^3 distinct samples: every process fills those in its block and
  // rank 0 gets their sum (one process per sample, so the sum is the sample).
  std::vector<double> samples;
  if (split) {
    samples.assign(std::size_t(m) * m * m, 0.0);
    const auto& o = psi.offset();
    const auto first = [&](int a) { return (o[a] + s - 1) / s; };  // first lattice index inside
    for (int c = first(2); c * s < o[2] + psi.nz(); ++c)
      for (int b = first(1); b * s < o[1] + psi.ny(); ++b)
        for (int a = first(0); a * s < o[0] + psi.nx(); ++a)
          samples[(std::size_t(c) * m + b) * m + a] = psi(a * s - o[0], b * s - o[1], c * s - o[2]);
    d->sum_to_root(samples.data(), samples.size());
  }
  const bool root = !split || d->rank() == 0;
  TriMesh mesh;
  if (root) {
    NodeLattice lattice;
    lattice.nodes = {m + 1, m + 1, m + 1};  // the last node of each axis is the first's image
    lattice.periodic = false;
    lattice.origin = {0.5 * h, 0.5 * h, 0.5 * h};
    lattice.spacing = {s * h, s * h, s * h};
    lattice.layer = [&](int k, double* values) {
      for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= m; ++i)
          values[j * (m + 1) + i] =
              split ? samples[(std::size_t(k % m) * m + j % m) * m + i % m]
                    : psi((i * s) % n, (j * s) % n, (k * s) % n);
    };
    mesh = extract_isosurface(lattice, 0.0);
  }
  samples = {};
  // H and the normal at each vertex, from psi's full resolution. On a decomposed grid rank 0
  // sends the vertices; the process holding a vertex's interpolation cube (its low cell and
  // the ghosts above) computes them, and rank 0 gets the sum (one process per vertex).
  std::vector<double> values;
  std::size_t nv = mesh.vertices.size();
  if (split) {
    std::vector<double> positions;
    if (root) {
      positions.reserve(3 * nv);
      for (const Vec3& x : mesh.vertices) positions.insert(positions.end(), {x[0], x[1], x[2]});
    }
    d->broadcast_vector(positions);
    nv = positions.size() / 3;
    values.assign(4 * nv, 0.0);
    const auto& o = psi.offset();
    for (std::size_t v = 0; v < nv; ++v) {
      const Vec3 x{positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
      const std::array<int, 3> c = base_cell(x, h, n);
      if (c[0] < o[0] || c[0] >= o[0] + psi.nx() || c[1] < o[1] || c[1] >= o[1] + psi.ny() ||
          c[2] < o[2] || c[2] >= o[2] + psi.nz())
        continue;
      // Local indices: the cube's low cell is c; (c - floor) maps the unwrapped corner.
      std::array<int, 3> shift;
      for (int a = 0; a < 3; ++a) shift[a] = c[a] - int(std::floor(x[a] / h - 0.5)) - o[a];
      vertex_values(
          x, h,
          [&](int i, int j, int k) {
            return block_cell_values(psi, i + shift[0], j + shift[1], k + shift[2]);
          },
          &values[4 * v]);
    }
    d->sum_to_root(values.data(), values.size());
    if (!root) return {};
  } else {
    values.resize(4 * nv);
#pragma omp parallel for schedule(static) if (nv > 20000)
    for (std::size_t v = 0; v < nv; ++v)
      vertex_values(mesh.vertices[v], h,
                    [&](int i, int j, int k) { return cell_values(psi, i, j, k); }, &values[4 * v]);
  }

  DrawSurface out;
  out.lattice_cells = m;
  out.origin = float(0.5 * h);
  out.triangles = mesh.triangles;
  out.positions.resize(nv);
  out.normals.resize(nv);
  out.curvature.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    const Vec3& x = mesh.vertices[v];
    const double* g = &values[4 * v + 1];
    const double len = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    for (int a = 0; a < 3; ++a) {
      out.positions[v][a] = float(x[a]);
      out.normals[v][a] = len > 0.0 ? float(g[a] / len) : (a == 2 ? 1.0f : 0.0f);
    }
    out.curvature[v] = float(values[4 * v]);
  }
  return out;
}

double curvature_spread(const DrawSurface& s, double centre, double q) {
  std::vector<std::pair<double, double>> dev;  // (|H - centre|, area)
  dev.reserve(s.triangles.size());
  double total = 0.0;
  for (const auto& t : s.triangles) {
    const auto& a = s.positions[t[0]];
    const auto& b = s.positions[t[1]];
    const auto& c = s.positions[t[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2],
                 z = u[0] * v[1] - u[1] * v[0];
    const double area = 0.5 * std::sqrt(x * x + y * y + z * z);
    const double hm = (s.curvature[t[0]] + s.curvature[t[1]] + s.curvature[t[2]]) / 3.0;
    dev.emplace_back(std::abs(hm - centre), area);
    total += area;
  }
  if (dev.empty() || !(total > 0.0)) return 0.0;
  std::sort(dev.begin(), dev.end());
  double acc = 0.0;
  for (const auto& [d, w] : dev) {
    acc += w;
    if (acc >= q * total) return d;
  }
  return dev.back().first;
}

}  // namespace cmcsurf
