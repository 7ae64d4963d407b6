#include "measure/topology.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <unordered_set>
#include <vector>

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

template <bool kPhase2>
inline bool in_phase(double v, double level) {
  return kPhase2 ? v < level : v > level;
}

template <bool kPhase2>
std::int64_t euler_of(const Field& phi, double level) {
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
            for (int x = 0; x < 2; ++x)
              in[z][y][x] = in_phase<kPhase2>(phi(i - 1 + x, j - 1 + y, k - 1 + z), level);
        chi += local_euler(in);
      }
  double sum = double(chi);  // exact: |chi| <= 8 N^3 < 2^53
  sum = phi.sum_over_ranks(sum);
  return std::int64_t(sum);
}

template <bool kPhase2>
std::int64_t euler_of_ref(const Field& phi, double level) {
  const int n = phi.n();
  auto inside = [&](int i, int j, int k) {
    return in_phase<kPhase2>(phi((i + n) % n, (j + n) % n, (k + n) % n), level);
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

// Union-find over cell indices, with path halving.
struct DisjointSets {
  std::vector<std::int32_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  std::int32_t find(std::int32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(std::int32_t a, std::int32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace

std::int64_t euler_characteristic(const Field& phi, double level) {
  return euler_of<false>(phi, level);
}
std::int64_t euler_characteristic_ref(const Field& phi, double level) {
  return euler_of_ref<false>(phi, level);
}
std::int64_t euler_characteristic_phase2(const Field& phi, double level) {
  return euler_of<true>(phi, level);
}
std::int64_t euler_characteristic_phase2_ref(const Field& phi, double level) {
  return euler_of_ref<true>(phi, level);
}

PhaseComponents phase_components(const Field& phi, double level) {
  if (!phi.whole()) throw std::invalid_argument("phase_components: needs the whole grid");
  const int n = phi.n();
  if (double(n) * n * n >= 2147483647.0)
    throw std::invalid_argument("phase_components: grid too large for 32-bit labels");
  const auto id = [n](int i, int j, int k) {
    return std::int32_t((((k + n) % n) * n + (j + n) % n) * n + (i + n) % n);
  };
  const auto below = [&](int i, int j, int k) {
    return phi((i + n) % n, (j + n) % n, (k + n) % n) < level;
  };
  // A cell at the level itself belongs to neither phase (it is in neither closed-voxel union).
  const auto member = [&](int i, int j, int k, int p) {
    return p == 1 ? phi((i + n) % n, (j + n) % n, (k + n) % n) > level : below(i, j, k);
  };
  DisjointSets sets(std::size_t(n) * n * n);
  // The 13 forward neighbours of the 26: every neighbouring pair is visited once.
  static constexpr int kForward[13][3] = {{1, 0, 0},  {-1, 1, 0}, {0, 1, 0},  {1, 1, 0},
                                          {-1, -1, 1}, {0, -1, 1}, {1, -1, 1}, {-1, 0, 1},
                                          {0, 0, 1},  {1, 0, 1},  {-1, 1, 1}, {0, 1, 1},
                                          {1, 1, 1}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int p = 1; p <= 2; ++p) {
          if (!member(i, j, k, p)) continue;
          for (const auto& d : kForward)
            if (member(i + d[0], j + d[1], k + d[2], p))
              sets.join(id(i, j, k), id(i + d[0], j + d[1], k + d[2]));
        }
  PhaseComponents out;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::int32_t c = id(i, j, k);
        if (sets.find(c) != c) continue;
        if (member(i, j, k, 1)) ++out.phase1;
        else if (member(i, j, k, 2)) ++out.phase2;
      }
  // Adjacent (phase 1, phase 2) root pairs across voxel faces.
  std::unordered_set<std::uint64_t> pairs;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (!member(i, j, k, 1)) continue;
        for (int axis = 0; axis < 3; ++axis)
          for (int s = -1; s <= 1; s += 2) {
            const int a = i + (axis == 0) * s, b = j + (axis == 1) * s, c = k + (axis == 2) * s;
            if (!below(a, b, c)) continue;
            const std::uint64_t r1 = std::uint32_t(sets.find(id(i, j, k)));
            const std::uint64_t r2 = std::uint32_t(sets.find(id(a, b, c)));
            pairs.insert(r1 << 32 | r2);
          }
      }
  out.interfaces = std::int64_t(pairs.size());
  return out;
}

}  // namespace cmcsurf
