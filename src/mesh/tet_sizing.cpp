#include "mesh/tet_sizing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <tuple>

#include "mesh/tet_smooth.h"

namespace cmcsurf {

namespace {

using Off = std::array<int, 3>;
// A vertex seen from a frame: its index and its whole periods there.
using VKey = std::pair<std::int32_t, Off>;

Off add(const Off& a, const Off& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Off minus(const Off& a, const Off& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// An edge of the torus: its smaller vertex, the other and that one's periods relative to it.
struct Edge {
  std::int32_t u = 0, w = 0;
  Off rel{0, 0, 0};
  double length = 0.0;
};

// The torus mesh's edges (of the tets not marked dead), each once, with its length.
std::vector<Edge> torus_edges(const PeriodicTets& t, const std::vector<char>* dead) {
  std::vector<Edge> e;
  for (std::size_t i = 0; i < t.tets.size(); ++i) {
    if (dead && (*dead)[i]) continue;
    for (int q = 0; q < 4; ++q)
      for (int r = q + 1; r < 4; ++r) {
        std::int32_t u = t.tets[i][q], w = t.tets[i][r];
        Off ou, ow;
        for (int a = 0; a < 3; ++a) ou[a] = t.offsets[i][q][a], ow[a] = t.offsets[i][r][a];
        if (w < u) std::swap(u, w), std::swap(ou, ow);
        Edge x{u, w, minus(ow, ou), 0.0};
        const Vec3 &pu = t.vertices[std::size_t(u)], &pw = t.vertices[std::size_t(w)];
        Vec3 d;
        for (int a = 0; a < 3; ++a) d[a] = pw[a] + x.rel[a] - pu[a];
        x.length = std::sqrt(dot(d, d));
        e.push_back(x);
      }
  }
  const auto same = [](const Edge& a, const Edge& b) {
    return a.u == b.u && a.w == b.w && a.rel == b.rel;
  };
  std::sort(e.begin(), e.end(), [](const Edge& a, const Edge& b) {
    return std::tie(a.u, a.w, a.rel) < std::tie(b.u, b.w, b.rel);
  });
  e.erase(std::unique(e.begin(), e.end(), same), e.end());
  return e;
}

class Sizer {
 public:
  Sizer(PeriodicTets& t, const EdgeSizeBounds& b) : t_(t), b_(b) {
    dead_.assign(t.tets.size(), 0);
    mask_.assign(t.tets.size(), 0);
    incident_.resize(t.vertices.size());
    for (std::size_t i = 0; i < t.tets.size(); ++i)
      for (int q = 0; q < 4; ++q) incident_[std::size_t(t.tets[i][q])].push_back(std::uint32_t(i));
    for (const TorusFace& f : torus_boundary_faces(t)) mask_[f.tet] |= std::uint8_t(1u << f.skip);
  }

  std::vector<Edge> edges() const { return torus_edges(t_, &dead_); }

  // Collapses u into w (w at periods rel from u); false, counted by reason, when refused.
  bool collapse(std::int32_t u, std::int32_t w, const Off& rel, EdgeSizing& s) {
    // A vertex on a cell face stays on it: only into a vertex on the same faces.
    for (int a = 0; a < 3; ++a)
      if (pos(u)[a] == 0.0 && pos(w)[a] != 0.0) return ++s.refused_fixed, false;
    const bool u_surface = on_surface(u), w_surface = on_surface(w);
    if (u_surface && !boundary_edge(u, w, rel)) return ++s.refused_fixed, false;
    const std::vector<Star> su = star(u), sw = star(w);
    // Link condition (Dey et al.): Lk(u) and Lk(w) meet in Lk(uw) only, with a vertex at
    // infinity joined to the surface, so that the mesh and its surface stay manifolds.
    std::vector<VKey> lu, lw, luw;
    std::vector<std::pair<VKey, VKey>> eu, ew, euw;
    std::vector<VKey> bu, bw, buw;  // surface edges' far ends; surface faces' third corners
    std::vector<std::size_t> shell;
    for (const Star& x : su) {
      int qw = -1;
      for (int r = 0; r < 4; ++r)
        if (t_.tets[x.i][r] == w) {
          if (minus(off(x.i, r), x.o) != rel) return ++s.refused_topology, false;
          qw = r;
        }
      if (qw >= 0) shell.push_back(x.i);
      collect_link(x, {0, 0, 0}, lu, eu, bu);
      if (qw >= 0) {
        std::vector<VKey> ab;
        for (int r = 0; r < 4; ++r)
          if (r != x.q && r != qw) {
            ab.push_back(key(x, r, {0, 0, 0}));
            if (mask_[x.i] & (1u << (6 - x.q - qw - r))) buw.push_back(ab.back());
          }
        luw.insert(luw.end(), ab.begin(), ab.end());
        euw.push_back(std::minmax(ab[0], ab[1]));
      }
    }
    if (shell.empty()) return ++s.refused_topology, false;  // not an edge (any more)
    for (const Star& x : sw) collect_link(x, rel, lw, ew, bw);
    for (auto* v : {&lu, &lw, &luw, &bu, &bw, &buw}) unique_sort(*v);
    for (auto* v : {&eu, &ew, &euw}) unique_sort(*v);
    const VKey ku{u, {0, 0, 0}}, kw{w, rel};
    for (const VKey& a : intersect(lu, lw))
      if (a != ku && a != kw && !std::binary_search(luw.begin(), luw.end(), a))
        return ++s.refused_topology, false;
    for (const auto& e : intersect(eu, ew))
      if (!std::binary_search(euw.begin(), euw.end(), e)) return ++s.refused_topology, false;
    if (u_surface && w_surface)
      for (const VKey& a : intersect(bu, bw))
        if (a != ku && a != kw && !std::binary_search(buw.begin(), buw.end(), a))
          return ++s.refused_topology, false;
    // Geometry: u's other tets with w in its place stay positive and no worse than they were
    // (or above the floor); no edge grows past size_max; the surface stays near u.
    const Vec3 pu = pos(u);
    Vec3 pw = pos(w);
    for (int a = 0; a < 3; ++a) pw[a] += rel[a];
    double before = 180.0, after = 180.0;
    // The plane of three points holds u within the facet distance.
    auto near_u = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
      const Vec3 n = cross(sub(b, a), sub(c, a));
      const double nn = norm(n);
      return nn > 0 && std::abs(dot(n, sub(pu, a))) / nn <= b_.facet_distance;
    };
    for (const Star& x : su) {
      before = std::min(before, quality(x.i, -1, {}));
      if (std::find(shell.begin(), shell.end(), x.i) != shell.end()) {
        // A shell tet whose face (u, a, b) is on the surface leaves (w, a, b) there.
        int qw = 0;
        while (t_.tets[x.i][qw] != w) ++qw;
        if (!u_surface || !(mask_[x.i] & (1u << qw))) continue;
        std::array<Vec3, 3> f;
        int m = 0;
        for (int r = 0; r < 4; ++r)
          if (r != x.q) f[std::size_t(m++)] = at(key(x, r, {0, 0, 0}));
        if (!near_u(f[0], f[1], f[2])) return ++s.refused_surface, false;
        continue;
      }
      after = std::min(after, quality(x.i, x.q, pw, x.o));
      for (int r = 0; r < 4; ++r) {
        if (r == x.q) continue;
        const Vec3 pa = at(key(x, r, {0, 0, 0}));
        const double old_l = norm(sub(pa, pu)), new_l = norm(sub(pa, pw));
        if (b_.size_max > 0 && new_l > std::max(b_.size_max, old_l))
          return ++s.refused_length, false;
      }
      if (!u_surface) continue;
      for (int k = 0; k < 4; ++k) {
        if (k == x.q || !(mask_[x.i] & (1u << k))) continue;
        std::array<Vec3, 3> f;
        int m = 0;
        for (int r = 0; r < 4; ++r)
          if (r != k) f[std::size_t(m++)] = r == x.q ? pw : at(key(x, r, {0, 0, 0}));
        if (!near_u(f[0], f[1], f[2])) return ++s.refused_surface, false;
      }
    }
    if (!(after > 0.0) || after < std::min(before, kSizingFloorDeg))
      return ++s.refused_quality, false;
    for (const Star& x : su)
      for (int a : add(x.o, rel))
        if (a < -127 || a > 127) return ++s.refused_fixed, false;  // never at these sizes
    for (std::size_t i : shell) dead_[i] = 1;
    for (const Star& x : su) {
      if (dead_[x.i]) continue;
      const Off o = add(x.o, rel);
      t_.tets[x.i][x.q] = w;
      for (int a = 0; a < 3; ++a) t_.offsets[x.i][x.q][a] = std::int8_t(o[a]);
      incident_[std::size_t(w)].push_back(std::uint32_t(x.i));
    }
    incident_[std::size_t(u)].clear();
    update_masks(w);
    ++s.collapsed;
    return true;
  }

  // Splits the edge (u, w at rel) at its midpoint.
  bool split(std::int32_t u, std::int32_t w, const Off& rel, EdgeSizing& s) {
    const std::vector<Star> su = star(u);
    std::vector<std::pair<Star, int>> shell;  // u's corner and w's
    for (const Star& x : su)
      for (int r = 0; r < 4; ++r)
        if (t_.tets[x.i][r] == w && minus(off(x.i, r), x.o) == rel) shell.push_back({x, r});
    if (shell.empty()) return false;
    const Vec3 pu = pos(u);
    Vec3 mid;
    Off shift{0, 0, 0};
    for (int a = 0; a < 3; ++a) {
      // Exactly 0 where both ends are on the face (0 + 0); else wrapped into [0, 1).
      const double y = 0.5 * (pu[a] + pos(w)[a] + rel[a]);
      int f = int(std::floor(y));
      double r = y - f;
      if (r >= 1.0) r -= 1.0, ++f;
      mid[a] = r, shift[a] = f;
    }
    const double half = 0.5 * distance(u, {0, 0, 0}, w, rel);
    if (b_.size_min > 0 && half < b_.size_min) return ++s.split_refused, false;
    Vec3 pm;
    for (int a = 0; a < 3; ++a) pm[a] = mid[a] + shift[a];
    double before = 180.0, after = 180.0;
    for (const auto& [x, qw] : shell) {
      before = std::min(before, quality(x.i, -1, {}));
      after = std::min({after, quality(x.i, x.q, pm, x.o), quality(x.i, qw, pm, x.o)});
      for (int r = 0; r < 4; ++r)
        if (r != x.q && r != qw && b_.size_min > 0 &&
            norm(sub(at(key(x, r, {0, 0, 0})), pm)) < b_.size_min)
          return ++s.split_refused, false;
    }
    if (!(after > 0.0) || after < std::min(before, kSizingFloorDeg))
      return ++s.split_refused, false;
    const std::int32_t m = std::int32_t(t_.vertices.size());
    t_.vertices.push_back(mid);
    incident_.emplace_back();
    for (const auto& [x, qw] : shell) {
      const Off om = add(x.o, shift);
      const std::size_t j = t_.tets.size();
      const auto tet = t_.tets[x.i];
      const auto offsets = t_.offsets[x.i];
      t_.tets.push_back(tet);
      t_.offsets.push_back(offsets);
      dead_.push_back(0);
      // Tet x.i keeps w and takes m for u; j keeps u and takes m for w. The face opposite m
      // is the old face opposite the corner it replaced; the new face between them is inside.
      const std::uint8_t old = mask_[x.i];
      auto place = [&](std::size_t i, int q, int other) {
        t_.tets[i][q] = m;
        for (int a = 0; a < 3; ++a) t_.offsets[i][q][a] = std::int8_t(om[a]);
        return std::uint8_t(old & ~(1u << other));
      };
      mask_[x.i] = place(x.i, x.q, qw);
      mask_.push_back(place(j, qw, x.q));
      incident_[std::size_t(m)].push_back(std::uint32_t(x.i));
      for (int r = 0; r < 4; ++r)
        incident_[std::size_t(t_.tets[j][r])].push_back(std::uint32_t(j));
    }
    ++s.split;
    return true;
  }

  // Drops the removed tets and the vertices no tet uses, keeping the order.
  void compact() {
    std::size_t k = 0;
    for (std::size_t i = 0; i < t_.tets.size(); ++i)
      if (!dead_[i]) t_.tets[k] = t_.tets[i], t_.offsets[k] = t_.offsets[i], ++k;
    t_.tets.resize(k), t_.offsets.resize(k);
    std::vector<std::int32_t> id(t_.vertices.size(), -1);
    for (const auto& tet : t_.tets)
      for (auto v : tet) id[std::size_t(v)] = 0;
    std::int32_t n = 0;
    for (std::size_t v = 0; v < id.size(); ++v)
      if (id[v] == 0) t_.vertices[std::size_t(n)] = t_.vertices[v], id[v] = n++;
    t_.vertices.resize(std::size_t(n));
    for (auto& tet : t_.tets)
      for (auto& v : tet) v = id[std::size_t(v)];
  }

  bool alive(std::int32_t v) const {
    for (auto i : incident_[std::size_t(v)])
      if (!dead_[i] && corner(i, v) >= 0) return true;
    return false;
  }

 private:
  struct Star {
    std::size_t i = 0;  // tet
    int q = 0;          // the centre's corner
    Off o{0, 0, 0};     // the centre's periods in it
  };

  template <class T>
  static void unique_sort(std::vector<T>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  template <class T>
  static std::vector<T> intersect(const std::vector<T>& a, const std::vector<T>& b) {
    std::vector<T> r;
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(r));
    return r;
  }

  const Vec3& pos(std::int32_t v) const { return t_.vertices[std::size_t(v)]; }
  Off off(std::size_t i, int q) const {
    return {t_.offsets[i][q][0], t_.offsets[i][q][1], t_.offsets[i][q][2]};
  }
  int corner(std::size_t i, std::int32_t v) const {
    for (int q = 0; q < 4; ++q)
      if (t_.tets[i][q] == v) return q;
    return -1;
  }
  Vec3 at(const VKey& k) const {
    const Vec3& p = pos(k.first);
    return {p[0] + k.second[0], p[1] + k.second[1], p[2] + k.second[2]};
  }
  double distance(std::int32_t u, const Off& ou, std::int32_t w, const Off& ow) const {
    return norm(sub(at({w, ow}), at({u, ou})));
  }
  // Corner r of the star tet x in the centre's frame, moved by shift periods.
  VKey key(const Star& x, int r, const Off& shift) const {
    return {t_.tets[x.i][r], add(minus(off(x.i, r), x.o), shift)};
  }

  std::vector<Star> star(std::int32_t v) const {
    std::vector<Star> s;
    for (auto i : incident_[std::size_t(v)]) {
      if (dead_[i]) continue;
      const int q = corner(i, v);
      if (q >= 0) s.push_back({i, q, off(i, q)});
    }
    std::sort(s.begin(), s.end(), [](const Star& a, const Star& b) { return a.i < b.i; });
    s.erase(std::unique(s.begin(), s.end(),
                        [](const Star& a, const Star& b) { return a.i == b.i; }),
            s.end());
    return s;
  }

  // The link of the centre in tet x (vertices, edges), and the far ends of its surface edges,
  // in the frame of u (shift: the centre's periods there).
  void collect_link(const Star& x, const Off& shift, std::vector<VKey>& lv,
                    std::vector<std::pair<VKey, VKey>>& le, std::vector<VKey>& bv) const {
    std::array<VKey, 3> f;
    int m = 0;
    for (int r = 0; r < 4; ++r)
      if (r != x.q) f[std::size_t(m++)] = key(x, r, shift);
    for (int a = 0; a < 3; ++a) {
      lv.push_back(f[std::size_t(a)]);
      le.push_back(std::minmax(f[std::size_t(a)], f[std::size_t((a + 1) % 3)]));
    }
    for (int k = 0; k < 4; ++k)
      if (k != x.q && (mask_[x.i] & (1u << k)))
        for (int r = 0; r < 4; ++r)
          if (r != x.q && r != k) bv.push_back(key(x, r, shift));
  }

  bool on_surface(std::int32_t v) const {
    for (const Star& x : star(v))
      for (int k = 0; k < 4; ++k)
        if (k != x.q && (mask_[x.i] & (1u << k))) return true;
    return false;
  }

  bool boundary_edge(std::int32_t u, std::int32_t w, const Off& rel) const {
    for (const Star& x : star(u))
      for (int r = 0; r < 4; ++r)
        if (t_.tets[x.i][r] == w && minus(off(x.i, r), x.o) == rel)
          for (int k = 0; k < 4; ++k)
            if (k != x.q && k != r && (mask_[x.i] & (1u << k))) return true;
    return false;
  }

  // Tet i's smallest dihedral angle, its corner q (if >= 0) moved to p in the frame where
  // that corner has periods o.
  double quality(std::size_t i, int q, const Vec3& p, const Off& o = {0, 0, 0}) const {
    std::array<Vec3, 4> x;
    for (int r = 0; r < 4; ++r) {
      if (r == q) {
        for (int a = 0; a < 3; ++a) x[std::size_t(r)][a] = p[a] + o[a];
        continue;
      }
      x[std::size_t(r)] = at({t_.tets[i][r], off(i, r)});
    }
    return tet_min_dihedral_deg(x[0], x[1], x[2], x[3]);
  }

  // Recounts the faces around w: one held by a single tet of its star is on the surface.
  void update_masks(std::int32_t w) {
    const std::vector<Star> sw = star(w);
    std::vector<std::array<VKey, 3>> faces;
    auto face = [&](const Star& x, int k) {
      std::array<VKey, 3> f;
      int m = 0;
      for (int r = 0; r < 4; ++r)
        if (r != k) f[std::size_t(m++)] = key(x, r, {0, 0, 0});
      std::sort(f.begin(), f.end());
      return f;
    };
    for (const Star& x : sw)
      for (int k = 0; k < 4; ++k)
        if (k != x.q) faces.push_back(face(x, k));
    std::sort(faces.begin(), faces.end());
    for (const Star& x : sw)
      for (int k = 0; k < 4; ++k) {
        if (k == x.q) continue;
        const auto f = face(x, k);
        const auto [lo, hi] = std::equal_range(faces.begin(), faces.end(), f);
        if (hi - lo == 1)
          mask_[x.i] |= std::uint8_t(1u << k);
        else
          mask_[x.i] &= std::uint8_t(~(1u << k));
      }
  }

  PeriodicTets& t_;
  const EdgeSizeBounds& b_;
  std::vector<char> dead_;
  std::vector<std::uint8_t> mask_;  // per tet: bit k, the face opposite corner k is surface
  std::vector<std::vector<std::uint32_t>> incident_;
};

}  // namespace

std::pair<std::size_t, std::size_t> count_edges_outside(const PeriodicTets& t, double lo,
                                                        double hi) {
  std::size_t below = 0, above = 0;
  for (const Edge& e : torus_edges(t, nullptr)) {
    below += lo > 0 && e.length < lo;
    above += hi > 0 && e.length > hi;
  }
  return {below, above};
}

EdgeSizing enforce_edge_sizes(PeriodicTets& t, const EdgeSizeBounds& b) {
  EdgeSizing s;
  std::tie(s.below_min_before, s.above_max_before) =
      count_edges_outside(t, b.size_min, b.size_max);
  Sizer z(t, b);
  constexpr int kPasses = 4;  // measured: a fifth pass finds nothing more
  for (int pass = 0; pass < kPasses && b.size_min > 0; ++pass) {
    std::vector<Edge> e = z.edges();
    e.erase(std::remove_if(e.begin(), e.end(),
                           [&](const Edge& x) { return !(x.length < b.size_min); }),
            e.end());
    std::stable_sort(e.begin(), e.end(),
                     [](const Edge& a, const Edge& c) { return a.length < c.length; });
    const std::size_t done = s.collapsed;
    // Refusals of the edges neither of whose ends could go (by the first end's reason): the
    // last pass's are what is left.
    EdgeSizing refused;
    for (const Edge& x : e) {
      if (!z.alive(x.u) || !z.alive(x.w)) continue;
      EdgeSizing first, second;
      if (z.collapse(x.u, x.w, x.rel, first) ||
          z.collapse(x.w, x.u, minus(Off{0, 0, 0}, x.rel), second)) {
        ++s.collapsed;
        continue;
      }
      refused.refused_fixed += first.refused_fixed;
      refused.refused_topology += first.refused_topology;
      refused.refused_quality += first.refused_quality;
      refused.refused_length += first.refused_length;
      refused.refused_surface += first.refused_surface;
    }
    s.refused_fixed = refused.refused_fixed, s.refused_topology = refused.refused_topology;
    s.refused_quality = refused.refused_quality, s.refused_length = refused.refused_length;
    s.refused_surface = refused.refused_surface;
    if (s.collapsed == done) break;
  }
  for (int pass = 0; pass < kPasses && b.size_max > 0; ++pass) {
    std::vector<Edge> e = z.edges();
    e.erase(std::remove_if(e.begin(), e.end(),
                           [&](const Edge& x) { return !(x.length > b.size_max); }),
            e.end());
    std::stable_sort(e.begin(), e.end(),
                     [](const Edge& a, const Edge& c) { return a.length > c.length; });
    const std::size_t done = s.split;
    EdgeSizing scratch;
    for (const Edge& x : e) z.split(x.u, x.w, x.rel, scratch);
    s.split += scratch.split;
    if (pass == kPasses - 1 || s.split == done) s.split_refused = scratch.split_refused;
    if (s.split == done) break;
  }
  z.compact();
  std::tie(s.below_min_after, s.above_max_after) = count_edges_outside(t, b.size_min, b.size_max);
  return s;
}

}  // namespace cmcsurf
