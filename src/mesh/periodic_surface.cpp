#include "mesh/periodic_surface.h"

#include <cmath>

#include "measure/sharp_surface.h"
#include "mesh/scaffold.h"

namespace cmcsurf {

TriMesh PeriodicSurfaceMesh::tri_mesh() const {
  TriMesh m;
  m.vertices = vertices;
  m.triangles = triangles;
  m.period = {1.0, 1.0, 1.0};
  return m;
}

PeriodicSurfaceMesh periodic_surface(const Field& psi) {
  CMCSURF_CHECK(psi.whole() && psi.ghost() >= 1);
  const int n = psi.n();
  const double inv_h = n;
  const TriMesh m = periodic_surface_mesh(psi, 0.0);
  PeriodicSurfaceMesh out;
  out.triangles = m.triangles;
  out.vertices.reserve(m.vertices.size());
  for (Vec3 v : m.vertices) {
    for (double& x : v) x -= std::floor(x);  // the lattice's last edges end past 1
    out.vertices.push_back(v);
  }
  // Each corner's image next to the first corner, by the minimum-image edge.
  out.offsets.reserve(m.triangles.size());
  for (const auto& t : m.triangles) {
    std::array<std::array<std::int32_t, 3>, 3> o{};
    for (int q = 1; q < 3; ++q) {
      const Vec3 e = mesh_edge(m, t[0], t[q]);
      for (int c = 0; c < 3; ++c)
        o[q][c] = std::int32_t(
            std::lround(out.vertices[t[0]][c] + e[c] - out.vertices[t[q]][c]));
    }
    out.offsets.push_back(o);
  }
  // Per cell: H, K and grad psi, computed where a vertex needs them.
  const std::ptrdiff_t sy = psi.stride_y(), sz = psi.stride_z();
  auto wrap = [n](int i) { return ((i % n) + n) % n; };
  const std::size_t nv = out.vertices.size();
  out.normals.resize(nv);
  out.mean_curvature.resize(nv);
  out.gaussian_curvature.resize(nv);
#pragma omp parallel for schedule(static)
  for (std::size_t v = 0; v < nv; ++v) {
    // The dual cube around the vertex: cell centres (i + 1/2) / n.
    double base[3], frac[3];
    int lo[3];
    for (int c = 0; c < 3; ++c) {
      base[c] = out.vertices[v][c] * n - 0.5;
      lo[c] = int(std::floor(base[c]));
      frac[c] = base[c] - lo[c];
    }
    double h = 0.0, k = 0.0, g[3] = {0.0, 0.0, 0.0};
    for (int corner = 0; corner < 8; ++corner) {
      const int d[3] = {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
      double w = 1.0;
      for (int c = 0; c < 3; ++c) w *= d[c] ? frac[c] : 1.0 - frac[c];
      const double* p =
          &psi(wrap(lo[0] + d[0]), wrap(lo[1] + d[1]), wrap(lo[2] + d[2]));
      h += w * level_set_mean_curvature(p, sy, sz, inv_h);
      k += w * level_set_gaussian_curvature(p, sy, sz, inv_h);
      g[0] += w * (p[1] - p[-1]);
      g[1] += w * (p[sy] - p[-sy]);
      g[2] += w * (p[sz] - p[-sz]);
    }
    const double norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    for (int c = 0; c < 3; ++c) out.normals[v][c] = norm > 0.0 ? -g[c] / norm : 0.0;
    out.mean_curvature[v] = h;
    out.gaussian_curvature[v] = k;
  }
  return out;
}

}  // namespace cmcsurf
