#include "render/draw_surface.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

DrawSurface draw_surface(const Field& psi, int max_cells) {
  if (!psi.whole()) throw std::invalid_argument("draw_surface: needs the whole grid");
  require_ghost(psi, 2, "draw_surface");
  CMCSURF_DCHECK(halo_is_current(psi));  // the curvature stencil reads the ghosts
  if (max_cells < 2) throw std::invalid_argument("draw_surface: max_cells must be >= 2");
  const int n = psi.n();
  const int s = draw_stride(n, max_cells);
  const int m = n / s;
  const double h = psi.h();
  NodeLattice lattice;
  lattice.nodes = {m + 1, m + 1, m + 1};  // the last node of each axis is the first's image
  lattice.periodic = false;
  lattice.origin = {0.5 * h, 0.5 * h, 0.5 * h};
  lattice.spacing = {s * h, s * h, s * h};
  lattice.layer = [&](int k, double* values) {
    const int kk = (k * s) % n;
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i <= m; ++i) values[j * (m + 1) + i] = psi((i * s) % n, (j * s) % n, kk);
  };
  const TriMesh mesh = extract_isosurface(lattice, 0.0);

  DrawSurface out;
  out.lattice_cells = m;
  out.origin = float(0.5 * h);
  out.triangles = mesh.triangles;
  const std::size_t nv = mesh.vertices.size();
  out.positions.resize(nv);
  out.normals.resize(nv);
  out.curvature.resize(nv);
#pragma omp parallel for schedule(static) if (nv > 20000)
  for (std::size_t v = 0; v < nv; ++v) {
    const Vec3& x = mesh.vertices[v];
    // Trilinear interpolation between the eight cell centres around x.
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
      const CellValues cv = cell_values(psi, c[0] + dx, c[1] + dy, c[2] + dz);
      hv += w * cv.h;
      for (int a = 0; a < 3; ++a) g[a] += w * cv.g[a];
    }
    const double len = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    for (int a = 0; a < 3; ++a) {
      out.positions[v][a] = float(x[a]);
      out.normals[v][a] = len > 0.0 ? float(g[a] / len) : (a == 2 ? 1.0f : 0.0f);
    }
    out.curvature[v] = float(hv);
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
