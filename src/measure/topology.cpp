#include "measure/topology.h"

#include "grid/check.h"

namespace cmcsurf {

namespace {

// The contribution of lattice vertex (i, j, k) (the low corner of voxel (i, j, k)) and of the
// edges and faces that start there along +x, +y, +z: in[z][y][x] says whether voxel
// (i - 1 + x, j - 1 + y, k - 1 + z) is in phase 1. Every vertex, edge, face and cube of the
// periodic lattice is counted by exactly one (i, j, k).
inline int local_euler(const bool in[2][2][2]) {
  const auto any = [&](int x0, int x1, int y0, int y1, int z0, int z1) {
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x)
          if (in[z][y][x]) return 1;
    return 0;
  };
  const int vertex = any(0, 1, 0, 1, 0, 1);
  const int edges = any(1, 1, 0, 1, 0, 1) + any(0, 1, 1, 1, 0, 1) + any(0, 1, 0, 1, 1, 1);
  const int faces = any(1, 1, 1, 1, 0, 1) + any(1, 1, 0, 1, 1, 1) + any(0, 1, 1, 1, 1, 1);
  const int cube = in[1][1][1] ? 1 : 0;
  return vertex - edges + faces - cube;
}

}  // namespace

std::int64_t euler_characteristic(const Field& phi, double level) {
  require_ghost(phi, 1, "euler_characteristic");
  CMCSURF_DCHECK(halo_is_current(phi));
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  std::int64_t chi = 0;
#pragma omp parallel for schedule(static) reduction(+ : chi) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        bool in[2][2][2];
        for (int z = 0; z < 2; ++z)
          for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) in[z][y][x] = phi(i - 1 + x, j - 1 + y, k - 1 + z) > level;
        chi += local_euler(in);
      }
  double sum = double(chi);  // exact: |chi| <= 8 N^3 < 2^53
  sum = phi.sum_over_ranks(sum);
  return std::int64_t(sum);
}

std::int64_t euler_characteristic_ref(const Field& phi, double level) {
  const int n = phi.n();
  auto inside = [&](int i, int j, int k) {
    return phi((i + n) % n, (j + n) % n, (k + n) % n) > level;
  };
  // Count the closed cells of the complex directly: a cell is in it when a voxel around it is.
  std::int64_t vertices = 0, edges = 0, faces = 0, cubes = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        bool v = false, ex = false, ey = false, ez = false;
        for (int c = 0; c < 8; ++c) {
          const int a = c & 1, b = (c >> 1) & 1, d = (c >> 2) & 1;
          const bool in = inside(i - a, j - b, k - d);
          v = v || in;
          if (a == 0) ex = ex || in;
          if (b == 0) ey = ey || in;
          if (d == 0) ez = ez || in;
        }
        const bool fz = inside(i, j, k) || inside(i, j, k - 1);
        const bool fy = inside(i, j, k) || inside(i, j - 1, k);
        const bool fx = inside(i, j, k) || inside(i - 1, j, k);
        vertices += v;
        edges += ex + ey + ez;
        faces += fx + fy + fz;
        cubes += inside(i, j, k);
      }
  return vertices - edges + faces - cubes;
}

}  // namespace cmcsurf
