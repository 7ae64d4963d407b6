// For tests: the whole unit torus as m^3 cubes of 6 Kuhn tets, a PeriodicTets with known
// volume, angles and edge lengths; and what every unfolding of the whole torus must show.
#pragma once

#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "grid/kuhn.h"
#include "mesh/tet_mesh.h"

namespace cmcsurf {

// The volume of a periodic tet mesh, each tet unfolded by its offsets.
inline double torus_volume(const PeriodicTets& t) {
  double v = 0.0;
  for (std::size_t i = 0; i < t.tets.size(); ++i) {
    std::array<Vec3, 4> x;
    for (int q = 0; q < 4; ++q)
      for (int a = 0; a < 3; ++a)
        x[std::size_t(q)][a] = t.vertices[std::size_t(t.tets[i][q])][a] + t.offsets[i][q][a];
    v += tet_volume(x[0], x[1], x[2], x[3]);
  }
  return v;
}

// The lattice is shifted by `shift` cubes (0.37: no vertex on a face of the box, so every tet
// that crosses a face carries offsets) and each vertex moved by up to `jitter` cubes per axis
// at random (seeded); every tet stays positive for jitter < 0.2 (a Kuhn tet's heights are at
// least 1/sqrt(2) cubes).
inline PeriodicTets kuhn_torus(int m, double shift = 0.37, double jitter = 0.0,
                               unsigned seed = 1) {
  PeriodicTets t;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  auto id = [m](int i, int j, int k) { return std::int32_t((k * m + j) * m + i); };
  std::vector<std::array<int, 3>> wrap_of;  // whole periods taken off a vertex to place it
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        Vec3 p{(i + shift) / m, (j + shift) / m, (k + shift) / m};
        std::array<int, 3> w{};
        for (int a = 0; a < 3; ++a) {
          if (jitter > 0) p[a] += u(rng) / m;
          w[a] = int(std::floor(p[a]));
          p[a] -= w[a];
        }
        t.vertices.push_back(p);
        wrap_of.push_back(w);
      }
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        for (const auto& tet : kKuhnTets) {
          std::array<std::int32_t, 4> v;
          std::array<std::array<std::int8_t, 3>, 4> o;
          for (int c = 0; c < 4; ++c) {
            const int* d = kCubeCorner[tet[c]];
            const int a = i + d[0], b = j + d[1], e = k + d[2];
            v[c] = id(a % m, b % m, e % m);
            const auto& w = wrap_of[std::size_t(v[c])];
            o[c] = {std::int8_t(a / m + w[0]), std::int8_t(b / m + w[1]),
                    std::int8_t(e / m + w[2])};
          }
          // Half of the Kuhn tets are listed clockwise: turn them.
          const int* a = kCubeCorner[tet[0]];
          std::array<Vec3, 4> x;
          for (int c = 0; c < 4; ++c)
            for (int q = 0; q < 3; ++q) x[c][q] = kCubeCorner[tet[c]][q] - a[q];
          if (tet_volume(x[0], x[1], x[2], x[3]) < 0) std::swap(v[2], v[3]), std::swap(o[2], o[3]);
          t.tets.push_back(v);
          t.offsets.push_back(o);
        }
  return t;
}

// The lower half (in z) of the jittered Kuhn torus (jitter 0.15): a slab whose two boundary
// layers are the solid's surface.
inline PeriodicTets kuhn_torus_slab(int m, unsigned seed) {
  const PeriodicTets whole = kuhn_torus(m, 0.37, 0.15, seed);
  PeriodicTets t;
  t.vertices = whole.vertices;
  for (std::size_t i = 0; i < whole.tets.size(); ++i) {
    double z = 0.0;
    for (int q = 0; q < 4; ++q)
      z += 0.25 * (whole.vertices[std::size_t(whole.tets[i][q])][2] + whole.offsets[i][q][2]);
    if (z - std::floor(z) < 0.5) {
      t.tets.push_back(whole.tets[i]);
      t.offsets.push_back(whole.offsets[i]);
    }
  }
  return t;
}

// The whole torus unfolded (unfold_periodic_tets, after cut_at_cell_faces too) fills a block of the
// given volume to round-off, positive tets in one piece, its periodic faces matched face for
// face and its cut nodes paired with points one period away.
inline void expect_whole_torus_unfolded(const TetMeshStats& s, double volume) {
  EXPECT_NEAR(s.volume, volume, 1e-12 * volume);
  EXPECT_EQ(s.inverted, 0u);
  EXPECT_EQ(s.degenerate, 0u);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.unmatched_faces, 0u);
  EXPECT_EQ(s.unpaired_nodes, 0u);
  EXPECT_GT(s.periodic_faces, 0u);
  EXPECT_LT(s.pair_mismatch, 1e-15);
}

}  // namespace cmcsurf
