#include "measure/topology.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
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

// local_euler of every 2x2x2 neighbourhood, indexed by its bits: in[z][y][x] is bit
// 4 z + 2 y + x.
const std::array<std::int8_t, 256>& euler_table() {
  static const std::array<std::int8_t, 256> table = [] {
    std::array<std::int8_t, 256> t{};
    for (int m = 0; m < 256; ++m) {
      bool in[2][2][2];
      for (int b = 0; b < 8; ++b) in[b >> 2][b >> 1 & 1][b & 1] = (m >> b & 1) != 0;
      t[std::size_t(m)] = std::int8_t(local_euler(in));
    }
    return t;
  }();
  return table;
}

template <bool kPhase2>
std::int64_t euler_of(const Field& phi, double level) {
  require_ghost(phi, 1, "euler_characteristic");
  CMCSURF_DCHECK(halo_is_current(phi));
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const std::array<std::int8_t, 256>& table = euler_table();
  std::int64_t chi = 0;
  // Along a row the neighbourhood of vertex i is the four cells (y, z) of columns i - 1 and i:
  // each column's bits are found once and shifted into the low (x = 0) or high (x = 1) place.
#pragma omp parallel for schedule(static) reduction(+ : chi) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const double* r00 = &phi(0, j - 1, k - 1);
      const double* r10 = &phi(0, j, k - 1);
      const double* r01 = &phi(0, j - 1, k);
      const double* r11 = &phi(0, j, k);
      const auto column = [&](int i) {
        return unsigned(in_phase<kPhase2>(r00[i], level)) |
               unsigned(in_phase<kPhase2>(r10[i], level)) << 2 |
               unsigned(in_phase<kPhase2>(r01[i], level)) << 4 |
               unsigned(in_phase<kPhase2>(r11[i], level)) << 6;
      };
      unsigned low = column(-1);
      std::int64_t row = 0;
      for (int i = 0; i < nx; ++i) {
        const unsigned high = column(i);
        row += table[low | high << 1];
        low = high;
      }
      chi += row;
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
  std::unique_ptr<std::int32_t[]> parent;
  // Every index its own set.
  explicit DisjointSets(std::size_t n) : parent(new std::int32_t[n]) {
    std::iota(parent.get(), parent.get() + n, 0);
  }
  // Unset: the caller makes every index its own set (in the threads that will use it).
  struct Unset {};
  DisjointSets(std::size_t n, Unset) : parent(new std::int32_t[n]) {}
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

PhaseComponents phase_components_ref(const Field& phi, double level) {
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

namespace {

// The 13 forward neighbours of phase_components_ref, in-plane ones (dz = 0) first.
constexpr int kForwardInPlane = 4;
constexpr int kForward[13][3] = {{1, 0, 0},  {-1, 1, 0}, {0, 1, 0},  {1, 1, 0},  {-1, -1, 1},
                                 {0, -1, 1}, {1, -1, 1}, {-1, 0, 1}, {0, 0, 1},  {1, 0, 1},
                                 {-1, 1, 1}, {0, 1, 1},  {1, 1, 1}};

}  // namespace

PhaseComponents phase_components(const Field& phi, double level) {
  if (!phi.whole()) throw std::invalid_argument("phase_components: needs the whole grid");
  const int n = phi.n();
  if (double(n) * n * n >= 2147483647.0)
    throw std::invalid_argument("phase_components: grid too large for 32-bit labels");
  const std::size_t cells = std::size_t(n) * n * n;
  const auto wrap = [n](int i) { return i < 0 ? i + n : i >= n ? i - n : i; };
  const auto id = [n](int i, int j, int k) { return std::int32_t((k * n + j) * n + i); };
  // Each cell's phase: 1 above the level, 2 below, 0 at it (in neither closed-voxel union).
  // Both arrays are first written here, in parallel (no serial zeroing of 5 bytes a cell).
  std::unique_ptr<std::uint8_t[]> phase(new std::uint8_t[cells]);
  DisjointSets sets(cells, DisjointSets::Unset{});
#pragma omp parallel for schedule(static) if (n >= kParallelMinN)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double v = phi(i, j, k);
        const std::int32_t c = id(i, j, k);
        phase[std::size_t(c)] = v > level ? 1 : v < level ? 2 : 0;
        sets.parent[std::size_t(c)] = c;
      }
  // Joins each cell of row (j, k) with its forward neighbours d = first..last-1 of the same
  // phase. Pairs that the closure of the other joins connects anyway are skipped (most of a
  // bulk cell's 13), so the sets are the same. Along x the phase runs: c's next cell c + x of
  // the phase is joined first, and then
  //  - a neighbour n = c + d with d.x = 0 or 1 neighbours c + x as well, whose pair with it is
  //    joined by c + x (or by the rule below, which reaches back to c);
  //  - a neighbour n = c + d with d.x = -1, when c - x and n - x both have the phase, is
  //    joined through them: c - x joins n - x (or reaches further back by this rule), and
  //    n - x joins n along x. At i = 0 the rule does not apply, so every chain ends.
  // Only the pass within a slab skips; the pass across a slab boundary joins every pair, so
  // each pair skipped relies on a pair that some pass joins.
  const std::uint8_t* const ph = phase.get();
  const auto join_row = [&](int j, int k, int first, int last) {
    std::int32_t row[13];  // the first cell of each neighbour's row
    for (int d = first; d < last; ++d)
      row[d] = id(0, wrap(j + kForward[d][1]), wrap(k + kForward[d][2]));
    const std::int32_t here = id(0, j, k);
    const bool skip = n >= 3 && first == 0;
    for (int i = 0; i < n; ++i) {
      const std::int32_t c = here + i;
      const std::uint8_t p = ph[c];
      if (p == 0) continue;
      const int next = i + 1 < n ? i + 1 : 0, prev = i > 0 ? i - 1 : n - 1;
      const int prev2 = i >= 2 ? i - 2 : i - 2 + n;
      const bool run = skip && ph[here + next] == p;
      const bool back = skip && i >= 1 && ph[c - 1] == p;
      if (run && back) {  // inside a run (most cells): the same tests, without the table loop
        sets.join(c, here + next);
        for (const int d : {1, 4, 7, 10}) {
          if (d >= last) break;
          if (ph[row[d] + prev] == p && ph[row[d] + prev2] != p) sets.join(c, row[d] + prev);
        }
        continue;
      }
      for (int d = first; d < last; ++d) {
        const int dx = kForward[d][0];
        if (run && d > 0 && dx != -1) continue;
        const std::int32_t b = row[d] + (dx < 0 ? prev : dx > 0 ? next : i);
        if (ph[b] != p) continue;
        if (back && dx < 0 && ph[row[d] + prev2] == p) continue;
        sets.join(c, b);
      }
    }
  };
  // Each thread joins within its slab of planes, whose cells' sets hold only cells of the slab
  // (a root is the set's smallest index), so no two threads touch one parent; the pairs across
  // slab boundaries are joined after, in one thread. The counts do not depend on the order.
  std::vector<int> slab_ends;
#pragma omp parallel if (n >= kParallelMinN)
  {
    const int threads = omp_get_num_threads(), t = omp_get_thread_num();
    const int k0 = int(std::int64_t(n) * t / threads);
    const int k1 = int(std::int64_t(n) * (t + 1) / threads);
    for (int k = k0; k < k1; ++k)
      for (int j = 0; j < n; ++j) join_row(j, k, 0, k + 1 < k1 ? 13 : kForwardInPlane);
#pragma omp single
    for (int u = 0; u < threads; ++u) slab_ends.push_back(int(std::int64_t(n) * (u + 1) / threads));
  }
  for (const int k1 : slab_ends)  // an empty slab repeats its neighbour's end: joined twice
    if (k1 > 0)
      for (int j = 0; j < n; ++j) join_row(j, k1 - 1, kForwardInPlane, 13);
  // Every parent is at most its child (join keeps the smaller root, halving only shortens), so
  // one pass in index order points every cell at its root.
  std::int32_t* const parent = sets.parent.get();
  for (std::size_t c = 0; c < cells; ++c) parent[c] = parent[std::size_t(parent[c])];
  PhaseComponents out;
  std::int64_t roots1 = 0, roots2 = 0;
#pragma omp parallel for schedule(static) reduction(+ : roots1, roots2) if (n >= kParallelMinN)
  for (std::int64_t c = 0; c < std::int64_t(cells); ++c)
    if (sets.parent[std::size_t(c)] == std::int32_t(c)) {
      roots1 += phase[std::size_t(c)] == 1;
      roots2 += phase[std::size_t(c)] == 2;
    }
  out.phase1 = roots1;
  out.phase2 = roots2;
  // Adjacent (phase 1, phase 2) root pairs across voxel faces: each thread lists its own
  // (without repeats in a row), then one sorted list without repeats.
  const auto root = [&](std::int32_t a) { return sets.parent[std::size_t(a)]; };
  std::vector<std::uint64_t> pairs;
#pragma omp parallel if (n >= kParallelMinN)
  {
    std::vector<std::uint64_t> mine;
#pragma omp for schedule(static) nowait
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j) {
        // The first cells of this row and of the four rows sharing its faces.
        const std::int32_t here = id(0, j, k);
        const std::int32_t rows[4] = {id(0, wrap(j - 1), k), id(0, wrap(j + 1), k),
                                      id(0, j, wrap(k - 1)), id(0, j, wrap(k + 1))};
        for (int i = 0; i < n; ++i) {
          const std::int32_t c = here + i;
          if (ph[c] != 1) continue;
          const std::int32_t faces[6] = {here + (i > 0 ? i - 1 : n - 1),
                                         here + (i + 1 < n ? i + 1 : 0),
                                         rows[0] + i, rows[1] + i, rows[2] + i, rows[3] + i};
          for (const std::int32_t b : faces) {
            if (ph[b] != 2) continue;
            const std::uint64_t key =
                std::uint64_t(std::uint32_t(root(c))) << 32 | std::uint32_t(root(b));
            if (mine.empty() || mine.back() != key) mine.push_back(key);
          }
        }
      }
#pragma omp critical
    pairs.insert(pairs.end(), mine.begin(), mine.end());
  }
  std::sort(pairs.begin(), pairs.end());
  out.interfaces = std::int64_t(std::unique(pairs.begin(), pairs.end()) - pairs.begin());
  return out;
}

}  // namespace cmcsurf
