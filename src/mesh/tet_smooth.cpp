#include "mesh/tet_smooth.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace cmcsurf {

namespace {

using Off = std::array<int, 3>;

Vec3 corner_position(const PeriodicTets& t, std::size_t i, int q) {
  const Vec3& p = t.vertices[std::size_t(t.tets[i][q])];
  return {p[0] + t.offsets[i][q][0], p[1] + t.offsets[i][q][1], p[2] + t.offsets[i][q][2]};
}

// The torus mesh's boundary faces (faces of one tet, compared with their corners' offsets
// relative to the first): the solid's surface; the cut made no boundary on the torus.
struct Surface {
  std::vector<char> vertex;       // on a boundary face
  std::vector<std::uint8_t> face;  // per tet: bit k set when the face opposite corner k is one
  std::vector<TorusEdge> edges;  // edges of boundary faces, sorted
};
Off offset_of(const PeriodicTets& t, std::size_t i, int q) {
  return {t.offsets[i][q][0], t.offsets[i][q][1], t.offsets[i][q][2]};
}
Surface torus_surface(const PeriodicTets& t) {
  Surface s;
  s.vertex.assign(t.vertices.size(), 0);
  s.face.assign(t.tets.size(), 0);
  for (const TorusFace& f : torus_boundary_faces(t)) {
    for (const auto& [v, o] : f.corners) s.vertex[std::size_t(v)] = 1;
    s.face[f.tet] |= std::uint8_t(1u << f.skip);
    for (std::size_t a = 0; a < 3; ++a)
      for (std::size_t b = a + 1; b < 3; ++b) {
        const auto& [u, ou] = f.corners[a];
        const auto& [w, ow] = f.corners[b];
        s.edges.push_back(torus_edge(u, ou, w, ow));
      }
  }
  std::sort(s.edges.begin(), s.edges.end());
  s.edges.erase(std::unique(s.edges.begin(), s.edges.end()), s.edges.end());
  return s;
}

}  // namespace

double tet_min_dihedral_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const std::array<Vec3, 4> p{a, b, c, d};
  double lmax2 = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const Vec3 e = sub(p[j], p[i]);
      lmax2 = std::max(lmax2, dot(e, e));
    }
  if (tet_volume(a, b, c, d) <= 1e-12 * lmax2 * std::sqrt(lmax2)) return -1.0;
  // Outward normals of the faces opposite each corner; the angle at an edge is pi minus the
  // angle between the normals of its two faces.
  std::array<Vec3, 4> n;
  for (int k = 0; k < 4; ++k) {
    const Vec3 &q0 = p[(k + 1) % 4], &q1 = p[(k + 2) % 4], &q2 = p[(k + 3) % 4];
    Vec3 nk = cross(sub(q1, q0), sub(q2, q0));
    if (dot(nk, sub(p[k], q0)) > 0) nk = {-nk[0], -nk[1], -nk[2]};
    const double l = std::sqrt(dot(nk, nk));
    n[k] = {nk[0] / l, nk[1] / l, nk[2] / l};
  }
  double smallest = 180.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double cosine = std::clamp(dot(n[i], n[j]), -1.0, 1.0);
      smallest = std::min(smallest, 180.0 - std::acos(cosine) * 180.0 / std::numbers::pi);
    }
  return smallest;
}

SliverSmoothing smooth_slivers(PeriodicTets& t, double target_deg, int sweeps, double max_edge,
                               double min_edge, bool peel_slivers) {
  SliverSmoothing s;
  const std::size_t nv = t.vertices.size();
  std::size_t nt = t.tets.size();
  std::vector<std::vector<std::pair<std::uint32_t, int>>> incident(nv);
  for (std::size_t i = 0; i < nt; ++i)
    for (int q = 0; q < 4; ++q)
      incident[std::size_t(t.tets[i][q])].push_back({std::uint32_t(i), q});
  const Surface surf = torus_surface(t);
  const std::vector<char>& surface = surf.vertex;
  auto is_fixed = [&](std::size_t v) {
    const Vec3& p = t.vertices[v];
    return surface[v] || (p[0] == 0.0 && p[1] == 0.0 && p[2] == 0.0) || incident[v].empty();
  };
  for (std::size_t v = 0; v < nv; ++v) s.fixed_vertices += is_fixed(v);
  std::vector<double> quality(nt);
  for (std::size_t i = 0; i < nt; ++i)
    quality[i] = tet_min_dihedral_deg(corner_position(t, i, 0), corner_position(t, i, 1),
                                      corner_position(t, i, 2), corner_position(t, i, 3));
  auto below = [&](std::array<std::size_t, 18>& histogram) {
    std::size_t c = 0;
    for (double q : quality) {
      c += q < target_deg;
      ++histogram[std::min<std::size_t>(17, std::size_t(std::max(q, 0.0) / 10.0))];
    }
    return c;
  };
  s.min_dihedral_before = nt ? *std::min_element(quality.begin(), quality.end()) : 0.0;
  s.tets_below_target_before = below(s.histogram_before);

  // Tet i's smallest angle with vertex v (its corner q) at canonical position p.
  auto quality_with = [&](std::size_t i, std::size_t v, const Vec3& p) {
    std::array<Vec3, 4> x;
    for (int q = 0; q < 4; ++q) {
      x[std::size_t(q)] = corner_position(t, i, q);
      if (std::size_t(t.tets[i][q]) == v)
        for (int a = 0; a < 3; ++a) x[std::size_t(q)][a] = p[a] + t.offsets[i][q][a];
    }
    return tet_min_dihedral_deg(x[0], x[1], x[2], x[3]);
  };
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    std::vector<std::size_t> candidates;
    for (std::size_t i = 0; i < nt; ++i)
      if (quality[i] < target_deg)
        for (int q = 0; q < 4; ++q)
          if (!is_fixed(std::size_t(t.tets[i][q])))
            candidates.push_back(std::size_t(t.tets[i][q]));
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    if (candidates.empty()) break;
    ++s.sweeps;
    std::size_t moved = 0;
    for (const std::size_t v : candidates) {
      const auto& inc = incident[v];
      double current = 180.0;
      for (const auto& [i, q] : inc) current = std::min(current, quality[i]);
      if (current >= target_deg) continue;  // an earlier move mended its tets
      ++s.vertices_tried;
      const Vec3 p0 = t.vertices[v];
      // Free axes: a coordinate 0 is on a cell face and stays there; the others stay inside
      // (0, 1), so the vertex's tets keep to their cells.
      std::array<bool, 3> movable{};
      for (int a = 0; a < 3; ++a) movable[a] = p0[a] != 0.0;
      double lmin = INFINITY, lmax = 0.0, lap_w = 0.0;
      Vec3 lap{0, 0, 0};
      for (const auto& [i, q] : inc)
        for (int r = 0; r < 4; ++r) {
          if (r == q) continue;
          Vec3 e;
          for (int a = 0; a < 3; ++a)
            e[a] = corner_position(t, i, r)[a] - t.offsets[i][q][a] - p0[a];
          const double l = std::sqrt(dot(e, e));
          lmin = std::min(lmin, l), lmax = std::max(lmax, l);
          for (int a = 0; a < 3; ++a) lap[a] += e[a];
          lap_w += 1.0;
        }
      // No edge of the vertex may grow past the size asked for (or past its longest now), nor
      // shrink below the smallest size (or its shortest now).
      const double reach = std::max(max_edge, lmax);
      const double close = std::min(min_edge, lmin);
      auto worst = [&](const Vec3& p, std::size_t* at) {
        for (int a = 0; a < 3; ++a)
          if (movable[a] && !(p[a] > 0.0 && p[a] < 1.0)) return -1.0;
        double m = 180.0;
        for (const auto& [i, q] : inc) {
          for (int r = 0; r < 4; ++r) {
            if (r == q || (max_edge <= 0.0 && min_edge <= 0.0)) continue;
            Vec3 e;
            for (int a = 0; a < 3; ++a)
              e[a] = corner_position(t, i, r)[a] - t.offsets[i][q][a] - p[a];
            if (max_edge > 0.0 && dot(e, e) > reach * reach) return -1.0;
            if (min_edge > 0.0 && dot(e, e) < close * close) return -1.0;
          }
          const double qi = quality_with(i, v, p);
          if (qi < m) m = qi, *at = i;
          if (m < 0) break;
        }
        return m;
      };
      std::size_t at = inc.front().first;
      Vec3 best_p = p0;
      double best = worst(p0, &at);
      // First the Laplacian point (the neighbours' mean), damped until it helps.
      for (double lambda : {1.0, 0.5, 0.25}) {
        Vec3 p = p0;
        for (int a = 0; a < 3; ++a)
          if (movable[a]) p[a] += lambda * lap[a] / lap_w;
        std::size_t at_p = at;
        const double w = worst(p, &at_p);
        if (w > best) {
          best = w, best_p = p, at = at_p;
          break;
        }
      }
      // Then ascent on the worst tet's smallest angle (central differences), a step of a
      // tenth of the shortest edge halved until the smallest angle of all the tets grows.
      for (int it = 0; it < 10; ++it) {
        const double h = 1e-4 * lmin;
        Vec3 g{0, 0, 0};
        for (int a = 0; a < 3; ++a) {
          if (!movable[a]) continue;
          Vec3 up = best_p, down = best_p;
          up[a] += h, down[a] -= h;
          g[a] = (quality_with(at, v, up) - quality_with(at, v, down)) / (2 * h);
        }
        const double gn = std::sqrt(dot(g, g));
        if (!(gn > 0.0)) break;
        bool improved = false;
        for (double step = 0.1 * lmin; step > 1e-4 * lmin; step *= 0.5) {
          Vec3 p = best_p;
          for (int a = 0; a < 3; ++a) p[a] += step * g[a] / gn;
          std::size_t at_p = at;
          const double w = worst(p, &at_p);
          if (w > best + 1e-6) {
            best = w, best_p = p, at = at_p, improved = true;
            break;
          }
        }
        if (!improved) break;
      }
      if (best_p == p0 || !(best > current)) continue;
      t.vertices[v] = best_p;
      for (const auto& [i, q] : inc) quality[i] = quality_with(i, v, best_p);
      ++moved;
    }
    s.moves += moved;
    if (moved == 0) break;
  }
  // Left below the target: mostly tets whose corners are all on the surface. One with two or
  // three faces there is peeled off, as CGAL's exuder would, so the surface runs along its
  // other faces, within the sliver's small height of where it ran. Kept where the surface would
  // turn non-manifold (the edge that becomes a surface edge already is one; the apex of three
  // surface faces in another tet), and next to another peeled tet (one at a time there).
  // Each corner's image in the unit box: its offsets less the cell its tet lies in (as
  // unfold_periodic_tets places it), and how many tets use it.
  auto image_key = [&](std::size_t i, int q) {
    double c[3] = {0, 0, 0};
    for (int r = 0; r < 4; ++r)
      for (int a = 0; a < 3; ++a) c[a] += 0.25 * corner_position(t, i, r)[a];
    std::uint64_t key = std::uint64_t(t.tets[i][q]);
    for (int a = 0; a < 3; ++a)
      key = (key << 8) | (std::uint64_t(t.offsets[i][q][a] - int(std::floor(c[a])) + 128) & 0xff);
    return key;
  };
  std::unordered_map<std::uint64_t, int> image_uses;
  for (std::size_t i = 0; i < nt; ++i)
    for (int q = 0; q < 4; ++q) ++image_uses[image_key(i, q)];
  std::vector<char> peel(nt, 0), touched(nv, 0);
  for (std::size_t i = 0; i < nt; ++i) {
    if (!peel_slivers || !(quality[i] < target_deg)) continue;
    const unsigned mask = surf.face[i];
    const int faces = std::popcount(mask);
    if (faces != 2 && faces != 3) continue;
    // Nor where a corner's image in the box (a vertex on a cell face has one on each side) is
    // in this tet alone: that node would go, leaving its face's twin unmirrored.
    bool ok = true;
    for (int q = 0; q < 4; ++q)
      ok = ok && !touched[std::size_t(t.tets[i][q])] && image_uses[image_key(i, q)] > 1;
    // Nor with a face on a cell face: its twin would turn into surface, unmirrored.
    for (int skip = 0; skip < 4 && ok; ++skip)
      for (int a = 0; a < 3 && ok; ++a) {
        bool on = true;
        for (int q = 0; q < 4; ++q)
          on = on && (q == skip || t.vertices[std::size_t(t.tets[i][q])][a] == 0.0);
        ok = !on;
      }
    if (faces == 2) {
      int k[2], m = 0;
      for (int q = 0; q < 4; ++q)
        if (mask & (1u << q)) k[m++] = q;
      ok = ok && !std::binary_search(surf.edges.begin(), surf.edges.end(),
                                     torus_edge(t.tets[i][k[0]], offset_of(t, i, k[0]),
                                                t.tets[i][k[1]], offset_of(t, i, k[1])));
    } else {
      int apex = 0;
      while (mask & (1u << apex)) ++apex;
      ok = ok && incident[std::size_t(t.tets[i][apex])].size() == 1;
    }
    if (!ok) continue;
    peel[i] = 1;
    for (int q = 0; q < 4; ++q) touched[std::size_t(t.tets[i][q])] = 1;
    std::array<Vec3, 4> x;
    for (int q = 0; q < 4; ++q) x[std::size_t(q)] = corner_position(t, i, q);
    s.peeled_volume += tet_volume(x[0], x[1], x[2], x[3]);
    ++s.peeled;
  }
  if (s.peeled) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < nt; ++i)
      if (!peel[i]) {
        t.tets[k] = t.tets[i], t.offsets[k] = t.offsets[i], quality[k] = quality[i];
        ++k;
      }
    t.tets.resize(k), t.offsets.resize(k), quality.resize(k);
    nt = k;
  }
  s.min_dihedral_after = nt ? *std::min_element(quality.begin(), quality.end()) : 0.0;
  s.tets_below_target_after = below(s.histogram_after);
  return s;
}

}  // namespace cmcsurf
