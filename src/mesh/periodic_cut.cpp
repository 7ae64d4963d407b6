#include "mesh/periodic_cut.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "mesh/tet_smooth.h"

namespace cmcsurf {

namespace {

// A tet corner: a torus vertex plus whole periods.
struct Corner {
  std::int32_t v = 0;
  std::array<int, 3> o{0, 0, 0};
};

Vec3 position(const PeriodicTets& t, const Corner& c) {
  const Vec3& p = t.vertices[std::size_t(c.v)];
  return {p[0] + c.o[0], p[1] + c.o[1], p[2] + c.o[2]};
}

// The torus edges already cut (TorusEdge: mesh/tet_mesh.h).
struct EdgeHash {
  std::size_t operator()(const TorusEdge& e) const {
    std::size_t h = std::size_t(e.u) * 1000003u ^ std::size_t(e.w);
    for (int r : e.rel) h = h * 31u + std::size_t(r + 16);
    return h;
  }
};
// The vertex added on an edge, and its periods relative to the edge's u.
struct CutVertex {
  std::int32_t id = 0;
  std::array<int, 3> shift{0, 0, 0};
};

class Splitter {
 public:
  Splitter(PeriodicTets& t, int axis, CellFaceCut& stats) : t_(t), a_(axis), stats_(stats) {}

  // Splits every tet that the plane x_axis = k (k whole) crosses.
  void run() {
    std::vector<std::array<std::int32_t, 4>> tets;
    std::vector<std::array<std::array<std::int8_t, 3>, 4>> offsets;
    out_tets_ = &tets;
    out_offsets_ = &offsets;
    tets.reserve(t_.tets.size() + t_.tets.size() / 4);
    offsets.reserve(tets.capacity());
    for (std::size_t i = 0; i < t_.tets.size(); ++i) split(i);
    t_.tets = std::move(tets);
    t_.offsets = std::move(offsets);
  }

 private:
  void split(std::size_t i) {
    std::array<Corner, 4> c;
    for (int q = 0; q < 4; ++q) {
      c[q].v = t_.tets[i][q];
      for (int a = 0; a < 3; ++a) c[q].o[a] = t_.offsets[i][q][a];
    }
    int lo = c[0].o[a_], hi = lo;
    for (const Corner& q : c) lo = std::min(lo, q.o[a_]), hi = std::max(hi, q.o[a_]);
    if (hi - lo > 1)
      throw std::runtime_error("cut_at_cell_faces: a tet spans more than a cell");
    // A corner at periods o lies in [o, o + 1): below the plane k = hi when o < k, on it when
    // o == k and its coordinate is 0, above otherwise. Exact: no rounding decides a side.
    const int k = hi;
    std::array<int, 4> below{}, on{}, above{};
    int nb = 0, nz = 0, na = 0;
    for (int q = 0; q < 4; ++q) {
      if (c[q].o[a_] < k)
        below[nb++] = q;
      else if (t_.vertices[std::size_t(c[q].v)][a_] == 0.0)
        on[nz++] = q;
      else
        above[na++] = q;
    }
    if (nb == 0 || na == 0) {
      emit(c[0], c[1], c[2], c[3]);
      return;
    }
    ++stats_.split_tets;
    auto cut = [&](int b, int a) { return cut_vertex(c[b], c[a], k); };
    if (nb == 1 && na == 3) {
      const Corner x0 = cut(below[0], above[0]), x1 = cut(below[0], above[1]),
                   x2 = cut(below[0], above[2]);
      emit(c[below[0]], x0, x1, x2);
      prism({x0, x1, x2}, {c[above[0]], c[above[1]], c[above[2]]});
    } else if (nb == 3 && na == 1) {
      const Corner x0 = cut(below[0], above[0]), x1 = cut(below[1], above[0]),
                   x2 = cut(below[2], above[0]);
      emit(c[above[0]], x0, x1, x2);
      prism({x0, x1, x2}, {c[below[0]], c[below[1]], c[below[2]]});
    } else if (nb == 2 && na == 2) {
      const Corner x00 = cut(below[0], above[0]), x01 = cut(below[0], above[1]),
                   x10 = cut(below[1], above[0]), x11 = cut(below[1], above[1]);
      prism({c[below[0]], x00, x01}, {c[below[1]], x10, x11});
      prism({c[above[0]], x00, x10}, {c[above[1]], x01, x11});
    } else if (nb == 1 && nz == 1 && na == 2) {
      const Corner x0 = cut(below[0], above[0]), x1 = cut(below[0], above[1]);
      emit(c[below[0]], c[on[0]], x0, x1);
      pyramid(c[on[0]], {c[above[0]], c[above[1]], x1, x0});
    } else if (nb == 2 && nz == 1 && na == 1) {
      const Corner x0 = cut(below[0], above[0]), x1 = cut(below[1], above[0]);
      emit(c[above[0]], c[on[0]], x0, x1);
      pyramid(c[on[0]], {c[below[0]], c[below[1]], x1, x0});
    } else {  // one below, two on the plane, one above
      const Corner x = cut(below[0], above[0]);
      emit(c[below[0]], c[on[0]], c[on[1]], x);
      emit(c[above[0]], c[on[0]], c[on[1]], x);
    }
  }

  // The vertex where the edge (b, a) crosses the plane k, computed once per torus edge in the
  // frame of its smaller vertex, so every tet holding the edge gets the same point.
  Corner cut_vertex(const Corner& b, const Corner& a, int k) {
    const Corner& u = b.v < a.v ? b : a;
    const Corner& w = b.v < a.v ? a : b;
    const TorusEdge key = torus_edge(u.v, u.o, w.v, w.o);
    auto [it, fresh] = cuts_.try_emplace(key);
    if (fresh) {
      const Vec3 pu = t_.vertices[std::size_t(u.v)];
      Vec3 pw = t_.vertices[std::size_t(w.v)];
      for (int q = 0; q < 3; ++q) pw[q] += key.rel[q];
      const int plane = k - u.o[a_];
      const double s = (plane - pu[a_]) / (pw[a_] - pu[a_]);
      Vec3 p;
      for (int q = 0; q < 3; ++q) {
        if (q == a_) {
          p[q] = 0.0, it->second.shift[q] = plane;
          continue;
        }
        const double y = pu[q] + s * (pw[q] - pu[q]);
        int f = int(std::floor(y));
        double r = y - f;
        if (r >= 1.0) r -= 1.0, ++f;
        p[q] = r, it->second.shift[q] = f;
      }
      it->second.id = std::int32_t(t_.vertices.size());
      t_.vertices.push_back(p);
      ++stats_.cut_vertices;
    }
    Corner x;
    x.v = it->second.id;
    for (int q = 0; q < 3; ++q) x.o[q] = u.o[q] + it->second.shift[q];
    return x;
  }

  void emit(Corner p, Corner q, Corner r, Corner s) {
    const Vec3 a = position(t_, p), b = position(t_, q), c = position(t_, r),
               d = position(t_, s);
    double v = tet_volume(a, b, c, d);
    if (v < 0) std::swap(r, s), v = -v;
    double lmax = 0.0;
    for (const auto& [x, y] : {std::pair(a, b), {a, c}, {a, d}, {b, c}, {b, d}, {c, d}})
      lmax = std::max(lmax, std::sqrt(dot(sub(y, x), sub(y, x))));
    if (v <= 1e-12 * lmax * lmax * lmax) ++stats_.degenerate;
    std::array<std::int32_t, 4> tet{p.v, q.v, r.v, s.v};
    std::array<std::array<std::int8_t, 3>, 4> off;
    const std::array<const Corner*, 4> cs{&p, &q, &r, &s};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 3; ++j) off[i][j] = std::int8_t(cs[i]->o[j]);
    out_tets_->push_back(tet);
    out_offsets_->push_back(off);
  }

  // Apex over the quadrilateral q0 q1 q2 q3 (in cyclic order), cut along the diagonal from its
  // vertex of smallest index.
  void pyramid(const Corner& apex, const std::array<Corner, 4>& q) {
    int m = 0;
    for (int i = 1; i < 4; ++i)
      if (q[i].v < q[m].v) m = i;
    emit(apex, q[m], q[(m + 1) % 4], q[(m + 2) % 4]);
    emit(apex, q[m], q[(m + 2) % 4], q[(m + 3) % 4]);
  }

  // The prism with triangles A and B and lateral edges A_i B_i: each lateral quadrilateral is
  // cut from its smallest vertex; with the smallest of all six at A_0, that gives the tet
  // A_0 B_0 B_1 B_2 and the pyramid A_0 over A_1 A_2 B_2 B_1.
  void prism(std::array<Corner, 3> A, std::array<Corner, 3> B) {
    int m = 0;
    bool in_b = false;
    std::int32_t smallest = A[0].v;
    for (int i = 0; i < 3; ++i) {
      if (A[i].v < smallest) smallest = A[i].v, m = i, in_b = false;
      if (B[i].v < smallest) smallest = B[i].v, m = i, in_b = true;
    }
    if (in_b) std::swap(A, B);
    std::rotate(A.begin(), A.begin() + m, A.end());
    std::rotate(B.begin(), B.begin() + m, B.end());
    emit(A[0], B[0], B[1], B[2]);
    pyramid(A[0], {A[1], A[2], B[2], B[1]});
  }

  PeriodicTets& t_;
  int a_;
  CellFaceCut& stats_;
  std::unordered_map<TorusEdge, CutVertex, EdgeHash> cuts_;
  std::vector<std::array<std::int32_t, 4>>* out_tets_ = nullptr;
  std::vector<std::array<std::array<std::int8_t, 3>, 4>>* out_offsets_ = nullptr;
};

// Moves vertices that lie within `snap` of their shortest edge of a face x_axis = 0 (mod 1)
// onto it, or away from it to that distance, unless both would leave an incident tet with
// under a tenth of its volume.
void snap_to_cell_faces(PeriodicTets& t, int axis, double snap, CellFaceCut& stats) {
  const std::size_t nv = t.vertices.size();
  std::vector<double> shortest(nv, INFINITY);
  std::vector<std::vector<std::pair<std::size_t, int>>> incident(nv);
  for (std::size_t i = 0; i < t.tets.size(); ++i)
    for (int q = 0; q < 4; ++q) {
      incident[std::size_t(t.tets[i][q])].push_back({i, q});
      for (int r = q + 1; r < 4; ++r) {
        Vec3 d;
        for (int a = 0; a < 3; ++a)
          d[a] = t.vertices[std::size_t(t.tets[i][r])][a] + t.offsets[i][r][a] -
                 t.vertices[std::size_t(t.tets[i][q])][a] - t.offsets[i][q][a];
        const double l = std::sqrt(dot(d, d));
        for (int c : {q, r})
          shortest[std::size_t(t.tets[i][c])] = std::min(shortest[std::size_t(t.tets[i][c])], l);
      }
    }
  auto volume = [&](std::size_t i, std::size_t moved, const Vec3& p, const std::array<int, 3>& up) {
    std::array<Vec3, 4> x;
    for (int q = 0; q < 4; ++q) {
      const std::size_t v = std::size_t(t.tets[i][q]);
      for (int a = 0; a < 3; ++a)
        x[q][a] = (v == moved ? p[a] + up[a] : t.vertices[v][a]) + t.offsets[i][q][a];
    }
    return tet_volume(x[0], x[1], x[2], x[3]);
  };
  const int a = axis;
  for (std::size_t v = 0; v < nv; ++v) {
    const double reach = snap * shortest[v];
    const Vec3 p0 = t.vertices[v];
    const double x = p0[a];
    const bool near_0 = x > 0.0 && x < reach && x <= 1.0 - x;
    const bool near_1 = !near_0 && 1.0 - x < reach && 1.0 - x < x;
    if (!near_0 && !near_1) continue;
    // Onto the face; where that would flatten a tet, away from it to reach instead: either way
    // the split makes no piece thinner than about reach.
    for (const bool onto : {true, false}) {
      Vec3 p = p0;
      std::array<int, 3> up{0, 0, 0};  // moved onto x = 1: one period up, at 0
      const double gap = near_0 ? x : 1.0 - x;
      const double moved = onto ? gap : reach - gap;
      p[a] = onto ? 0.0 : near_0 ? reach : 1.0 - reach;
      up[a] = onto && near_1 ? 1 : 0;
      bool ok = true;
      for (const auto& [i, q] : incident[v])
        ok = ok && volume(i, v, p, up) >= 0.1 * volume(i, v, p0, {0, 0, 0});
      if (!ok) {
        if (!onto) ++stats.snaps_refused;
        continue;
      }
      t.vertices[v] = p;
      for (const auto& [i, q] : incident[v])
        for (int b = 0; b < 3; ++b) t.offsets[i][q][b] = std::int8_t(t.offsets[i][q][b] + up[b]);
      ++(onto ? stats.snapped : stats.pushed);
      stats.max_snap = std::max(stats.max_snap, moved);
      break;
    }
  }
}

using Incidence = std::vector<std::vector<std::pair<std::size_t, int>>>;

Incidence incidences(const PeriodicTets& t) {
  Incidence incident(t.vertices.size());
  for (std::size_t i = 0; i < t.tets.size(); ++i)
    for (int q = 0; q < 4; ++q) incident[std::size_t(t.tets[i][q])].push_back({i, q});
  return incident;
}

Vec3 corner_of(const PeriodicTets& t, std::size_t i, int q) {
  return position(t, {t.tets[i][q], {t.offsets[i][q][0], t.offsets[i][q][1],
                                     t.offsets[i][q][2]}});
}

double tet_min_dihedral(const PeriodicTets& t, std::size_t i) {
  return tet_min_dihedral_deg(corner_of(t, i, 0), corner_of(t, i, 1), corner_of(t, i, 2),
                              corner_of(t, i, 3));
}

double volume_of(const PeriodicTets& t, std::size_t i) {
  return tet_volume(corner_of(t, i, 0), corner_of(t, i, 1), corner_of(t, i, 2),
                    corner_of(t, i, 3));
}

// The faces v is on (bits).
unsigned planes_of(const PeriodicTets& t, std::size_t v) {
  unsigned planes = 0;
  for (int a = 0; a < 3; ++a) planes |= (t.vertices[v][a] == 0.0 ? 1u : 0u) << a;
  return planes;
}

// The cell around corner q of tet i that the tet lies in: bit a set when the tet is below face
// a (the corner on the upper plane of the tet's cell). After the cut every tet lies in one cell.
unsigned cell_of(const PeriodicTets& t, std::size_t i, int q, unsigned planes) {
  unsigned cell = 0;
  for (int a = 0; a < 3; ++a) {
    if (!(planes & (1u << a))) continue;
    double c = 0.0;
    for (int r = 0; r < 4; ++r) c += 0.25 * corner_of(t, i, r)[a];
    cell |= unsigned(t.offsets[i][q][a] - int(std::floor(c)) == 1) << a;
  }
  return cell;
}

// The cells around a point on the faces `planes`, as bits.
unsigned all_cells(unsigned planes) {
  unsigned want = 0;
  for (unsigned cell = 0; cell < 8; ++cell) want |= (cell & ~planes) ? 0u : 1u << cell;
  return want;
}

unsigned cells_of(const PeriodicTets& t, const std::vector<std::pair<std::size_t, int>>& inc,
                  unsigned planes) {
  unsigned cells = 0;
  for (const auto& [i, q] : inc) cells |= 1u << cell_of(t, i, q, planes);
  return cells;
}

// Face vertices with tets in some of the cells around them but not all: some of their images
// in the box lack a partner.
std::size_t face_vertices_in_part_of_cells(const PeriodicTets& t) {
  const Incidence incident = incidences(t);
  std::size_t n = 0;
  for (std::size_t v = 0; v < t.vertices.size(); ++v) {
    const unsigned planes = planes_of(t, v);
    n += planes && !incident[v].empty() && cells_of(t, incident[v], planes) != all_cells(planes);
  }
  return n;
}

// How one vertex's move off the faces went (move_into_middle_cell).
struct CellMove {
  bool moved = false;
  bool below_floor = false;     // kept by the second pass: under the floor, not the pairing's
  double h = 0.0;               // the largest distance off a face, unit cells
  double min_dihedral = 180.0;  // the smallest angle of the changed tets, degrees
  std::size_t recut = 0;        // tets split by the re-cut
};

// Moves v (on two or three faces, its tets in an L of the cells around it) into the cell of
// its tets joined across faces to the most others, off each face by h, and re-cuts the tets of
// the other cells at those faces. The pieces between v and the faces are about h thick, so h
// starts at the snap's reach (kDefaultCellFaceSnap of the shortest edge: the snap put v there
// by up to as much) and is halved while an incident tet would lose half its volume, a piece
// would be degenerate or a changed tet's smallest dihedral angle fall below `bound`, down to
// the lift's distance. Where none passes, a second pass (PairingMove in periodic_cut.h) tries
// moves up to kPairingMoveShares[0] of the shortest edge, smooths the free vertices of v's
// tets and its neighbours' tets, and keeps the best try above min(bound, kPairingFloorDeg).
// Unmoved: t unchanged. Each try works on a copy of those tets.
CellMove move_into_middle_cell(PeriodicTets& t, std::size_t v, double max_lift, double bound,
                               double min_edge, double max_edge) {
  CellMove result;
  const Incidence incident = incidences(t);
  const auto& inc = incident[v];
  const unsigned planes = planes_of(t, v);
  if (!planes || inc.empty()) return result;
  const unsigned cells = cells_of(t, inc, planes);
  // Where v may go: off the faces `off` to the sides `side` (bit a set: below face a), so
  // that on the faces it stays on its tets fill every cell around it. First the cell joined
  // across faces to the most others (off all faces), then off fewer faces (at a box corner
  // with 7 of the 8 cells, off one face onto an edge with all 4).
  unsigned middle = 0;
  int most = -1;
  for (unsigned c = 0; c < 8; ++c) {
    if (!(cells >> c & 1u)) continue;
    int joined = 0;
    for (int a = 0; a < 3; ++a)
      joined += (planes >> a & 1u) && (cells >> (c ^ (1u << a)) & 1u);
    if (joined > most) most = joined, middle = c;
  }
  std::vector<std::pair<unsigned, unsigned>> targets{{planes, middle}};
  for (int faces = 1; faces <= 3; ++faces)
    for (unsigned off = 1; off < 8; ++off) {
      if ((off & ~planes) || std::popcount(off) != faces) continue;
      for (unsigned side = 0; side < 8; ++side) {
        if (side & ~off) continue;
        bool fills = true;
        for (unsigned r = 0; r < 8; ++r)
          if (!(r & ~(planes & ~off))) fills = fills && (cells >> (side | r) & 1u);
        if (fills && !(off == planes && side == middle)) targets.push_back({off, side});
      }
    }
  double shortest = INFINITY;
  std::vector<double> before;
  for (const auto& [i, q] : inc) {
    before.push_back(volume_of(t, i));
    for (int r = 0; r < 4; ++r)
      if (r != q) {
        const Vec3 d = sub(corner_of(t, i, r), corner_of(t, i, q));
        shortest = std::min(shortest, std::sqrt(dot(d, d)));
      }
  }
  // Only v's tets change position: an edge the faces cross after the move has v at one end,
  // so every tet holding it is one of them. They come first in `part`; the second pass adds
  // the other tets of v's neighbours, whose free vertices it smooths.
  std::vector<char> in_part(t.tets.size(), 0);
  std::vector<std::size_t> part_tets;
  auto take = [&](std::size_t i) {
    if (in_part[i]) return;
    in_part[i] = 1;
    part_tets.push_back(i);
  };
  for (const auto& [i, q] : inc) take(i);
  // The part over its own vertices, numbered in the order of their indices in t, so that the
  // re-cut's diagonals (from the smallest index) and the smoothing's order are t's own, and
  // a try costs the part's size, not the mesh's.
  PeriodicTets part;
  std::vector<std::int32_t> global;
  std::int32_t local_v = 0;
  auto localize = [&] {
    global.clear();
    for (std::size_t i : part_tets) global.insert(global.end(), t.tets[i].begin(), t.tets[i].end());
    std::sort(global.begin(), global.end());
    global.erase(std::unique(global.begin(), global.end()), global.end());
    auto local = [&](std::int32_t g) {
      return std::int32_t(std::lower_bound(global.begin(), global.end(), g) - global.begin());
    };
    part = PeriodicTets{};
    for (std::int32_t g : global) part.vertices.push_back(t.vertices[std::size_t(g)]);
    for (std::size_t i : part_tets) {
      std::array<std::int32_t, 4> tet;
      for (int q = 0; q < 4; ++q) tet[q] = local(t.tets[i][q]);
      part.tets.push_back(tet);
      part.offsets.push_back(t.offsets[i]);
    }
    local_v = local(std::int32_t(v));
  };
  localize();
  // v off the faces `off` to the sides `side` by h, its tets re-cut (`recut` of them): the
  // smallest dihedral angle of the part's tets, or -1 where one of v's tets would lose half
  // its volume or a piece be degenerate.
  auto attempt = [&](double h, unsigned off, unsigned side, bool smooth, PeriodicTets& trial,
                     std::size_t& recut) {
    trial = part;
    for (int a = 0; a < 3; ++a) {
      if (!(off >> a & 1u)) continue;
      const bool below = side >> a & 1u;  // one period down, at 1 - h
      trial.vertices[std::size_t(local_v)][a] = below ? 1.0 - h : h;
      for (std::size_t k = 0; k < inc.size(); ++k) {
        std::int8_t& o = trial.offsets[k][inc[k].second][a];
        o = std::int8_t(o - (below ? 1 : 0));
      }
    }
    for (std::size_t k = 0; k < inc.size(); ++k)
      if (volume_of(trial, k) < 0.5 * before[k]) return -1.0;
    CellFaceCut stats;
    for (int axis = 0; axis < 3; ++axis) Splitter(trial, axis, stats).run();
    if (stats.degenerate) return -1.0;
    recut = stats.split_tets;
    auto smallest = [&] {
      double lowest = 180.0;
      for (std::size_t i = 0; i < trial.tets.size(); ++i)
        lowest = std::min(lowest, tet_min_dihedral(trial, i));
      return lowest;
    };
    const double lowest = smallest();
    // Smoothing gained at most 3.5 degrees in the tries measured: below a quarter of the
    // floor it is not worth its time (most tries, ~10 ms each).
    if (!smooth || lowest >= bound || lowest < 0.25 * kPairingFloorDeg) return lowest;
    smooth_slivers(trial, kSliverTargetDeg, kSliverSweeps, max_edge, min_edge, false);
    return smallest();
  };
  auto splice = [&](PeriodicTets& trial, double h, double lowest, std::size_t recut) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < t.tets.size(); ++i) {
      if (in_part[i]) continue;
      t.tets[kept] = t.tets[i];
      t.offsets[kept] = t.offsets[i];
      ++kept;
    }
    t.tets.resize(kept);
    t.offsets.resize(kept);
    // The part's vertices back (moved), the re-cut's new ones appended.
    const std::size_t n = global.size();
    const auto first_new = std::int32_t(t.vertices.size());
    for (std::size_t l = 0; l < trial.vertices.size(); ++l) {
      if (l < n)
        t.vertices[std::size_t(global[l])] = trial.vertices[l];
      else
        t.vertices.push_back(trial.vertices[l]);
    }
    for (auto tet : trial.tets) {
      for (std::int32_t& x : tet)
        x = std::size_t(x) < n ? global[std::size_t(x)] : first_new + (x - std::int32_t(n));
      t.tets.push_back(tet);
    }
    t.offsets.insert(t.offsets.end(), trial.offsets.begin(), trial.offsets.end());
    result.moved = true;
    result.h = h;
    result.min_dihedral = lowest;
    result.recut = recut;
  };
  const double least = std::min(kOneSidedLift * shortest, max_lift);
  PeriodicTets trial;
  std::size_t recut = 0;
  for (double h = kDefaultCellFaceSnap * shortest; h >= least; h *= 0.5)
    for (const auto& [off, side] : targets) {
      const double lowest = attempt(h, off, side, false, trial, recut);
      if (lowest >= bound) {
        splice(trial, h, lowest, recut);
        return result;
      }
    }
  // Second pass: a corner vertex is left unpaired by every move above, since its pieces are
  // tents of v's height over its neighbours' triangles on the faces. Farther moves, the
  // neighbours smoothed, the best try kept if above the pairing floor.
  for (const auto& [i, q] : inc)
    for (int r = 0; r < 4; ++r)
      for (const auto& [j, s] : incident[std::size_t(t.tets[i][r])]) take(j);
  localize();
  PeriodicTets best_trial;
  double best = -1.0, best_h = 0.0;
  std::size_t best_recut = 0;
  for (double share : kPairingMoveShares) {
    const double h = share * shortest;
    if (h < least) continue;
    for (const auto& [off, side] : targets) {
      const double lowest = attempt(h, off, side, true, trial, recut);
      if (lowest > best)
        best = lowest, best_h = h, best_recut = recut, best_trial = std::move(trial);
    }
  }
  if (best >= std::min(bound, kPairingFloorDeg)) {
    splice(best_trial, best_h, best, best_recut);
    result.below_floor = best < bound;
  }
  return result;
}

}  // namespace

OneSidedFaceVertices lift_one_sided_face_vertices(PeriodicTets& t, double max_lift,
                                                  double min_edge, double max_edge,
                                                  double floor_deg) {
  OneSidedFaceVertices s;
  std::vector<std::vector<std::pair<std::size_t, int>>> incident(t.vertices.size());
  for (std::size_t i = 0; i < t.tets.size(); ++i)
    for (int q = 0; q < 4; ++q) incident[std::size_t(t.tets[i][q])].push_back({i, q});
  auto corner = [&](std::size_t i, int q) {
    return position(t, {t.tets[i][q], {t.offsets[i][q][0], t.offsets[i][q][1],
                                       t.offsets[i][q][2]}});
  };
  auto volume = [&](std::size_t i) {
    return tet_volume(corner(i, 0), corner(i, 1), corner(i, 2), corner(i, 3));
  };
  // The faces v is on (bits), and the cell around it each incident tet lies in: bit a set
  // when the tet is below face a (v on the upper plane of the tet's cell). After the cut every
  // tet lies in one cell.
  auto planes_of = [&](std::size_t v) {
    unsigned planes = 0;
    for (int a = 0; a < 3; ++a) planes |= (t.vertices[v][a] == 0.0 ? 1u : 0u) << a;
    return planes;
  };
  auto cell_of = [&](std::size_t i, int q, unsigned planes) {
    unsigned cell = 0;
    for (int a = 0; a < 3; ++a) {
      if (!(planes & (1u << a))) continue;
      double c = 0.0;
      for (int r = 0; r < 4; ++r) c += 0.25 * corner(i, r)[a];
      cell |= unsigned(t.offsets[i][q][a] - int(std::floor(c)) == 1) << a;
    }
    return cell;
  };
  auto all_cells = [](unsigned planes) {
    unsigned want = 0;
    for (unsigned cell = 0; cell < 8; ++cell) want |= (cell & ~planes) ? 0u : 1u << cell;
    return want;
  };
  // An edge of v inside [min_edge, max_edge] (0: no bound) must stay inside.
  auto edges_inside = [&](std::size_t v) {
    std::vector<char> in;
    for (const auto& [i, q] : incident[v])
      for (int r = 0; r < 4; ++r) {
        if (r == q) continue;
        const Vec3 d = sub(corner(i, r), corner(i, q));
        const double l = std::sqrt(dot(d, d));
        in.push_back((min_edge <= 0 || l >= min_edge) && (max_edge <= 0 || l <= max_edge));
      }
    return in;
  };
  // Off face a into the cell of all v's tets (side 0: above it, 1: below).
  auto lift = [&](std::size_t v, int a, unsigned side) {
    double shortest = INFINITY;
    std::vector<double> before;
    for (const auto& [i, q] : incident[v]) {
      before.push_back(volume(i));
      for (int r = 0; r < 4; ++r)
        if (r != q) {
          const Vec3 d = sub(corner(i, r), corner(i, q));
          shortest = std::min(shortest, std::sqrt(dot(d, d)));
        }
    }
    const std::vector<char> inside = edges_inside(v);
    const Vec3 p0 = t.vertices[v];
    const int down = side == 0 ? 0 : 1;
    for (double h = std::min(kOneSidedLift * shortest, max_lift); h > 1e-9; h *= 0.5) {
      t.vertices[v][a] = side == 0 ? h : 1.0 - h;  // below: one period down
      for (const auto& [i, q] : incident[v])
        t.offsets[i][q][a] = std::int8_t(t.offsets[i][q][a] - down);
      bool ok = true;
      for (std::size_t k = 0; k < incident[v].size() && ok; ++k)
        ok = volume(incident[v][k].first) >= 0.5 * before[k];
      const std::vector<char> now = edges_inside(v);
      for (std::size_t k = 0; k < now.size() && ok; ++k) ok = now[k] || !inside[k];
      if (ok) {
        s.max_lift = std::max(s.max_lift, h);
        return true;
      }
      t.vertices[v] = p0;
      for (const auto& [i, q] : incident[v])
        t.offsets[i][q][a] = std::int8_t(t.offsets[i][q][a] + down);
    }
    return false;
  };
  std::vector<std::size_t> in_l;  // left on faces with tets in some cells around them
  for (std::size_t v = 0; v < t.vertices.size(); ++v) {  // grows by the copies below
    const unsigned planes = planes_of(v);
    if (!planes || incident[v].empty()) continue;
    unsigned cells = 0;
    for (const auto& [i, q] : incident[v]) cells |= 1u << cell_of(i, q, planes);
    if (cells == all_cells(planes)) continue;
    // Tets in cells that meet only along a line or at a point (diagonally): one copy of v per
    // group of cells joined across faces (v pinches the solid there), each lifted on its own
    // when the loop reaches it.
    std::array<int, 8> group{};
    for (unsigned c = 0; c < 8; ++c) group[c] = int(c);
    for (int sweep = 0; sweep < 3; ++sweep)
      for (unsigned c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a) {
          const unsigned d = c ^ (1u << a);
          if ((cells >> c & 1u) && (cells >> d & 1u) && (planes >> a & 1u))
            group[c] = group[d] = std::min(group[c], group[d]);
        }
    const int first = group[cell_of(incident[v][0].first, incident[v][0].second, planes)];
    std::array<std::int32_t, 8> copy;
    copy.fill(-1);
    std::vector<std::pair<std::size_t, int>> kept;
    for (const auto& [i, q] : incident[v]) {
      const int g = group[cell_of(i, q, planes)];
      if (g == first) {
        kept.push_back({i, q});
        continue;
      }
      if (copy[std::size_t(g)] < 0) {
        copy[std::size_t(g)] = std::int32_t(t.vertices.size());
        t.vertices.push_back(t.vertices[v]);
        incident.emplace_back();
        ++s.split;
      }
      t.tets[i][q] = copy[std::size_t(g)];
      incident[std::size_t(copy[std::size_t(g)])].push_back({i, q});
    }
    incident[v] = std::move(kept);
    for (int a = 0; a < 3; ++a) {
      if (!(planes & (1u << a))) continue;
      unsigned sides = 0;
      for (const auto& [i, q] : incident[v]) sides |= 1u << (cell_of(i, q, planes) >> a & 1u);
      if (sides == 3u) continue;
      ++s.found;
      s.lifted += lift(v, a, sides == 1u ? 0u : 1u);
    }
    const unsigned left = planes_of(v);
    unsigned now = 0;
    for (const auto& [i, q] : incident[v]) now |= 1u << cell_of(i, q, left);
    if (left && now != all_cells(left)) in_l.push_back(v);
  }
  // L vertices off the faces, each tried on a copy of its tets.
  if (!in_l.empty()) {
    double lowest = 180.0;
    for (std::size_t i = 0; i < t.tets.size(); ++i)
      lowest = std::min(lowest, tet_min_dihedral(t, i));
    const double bound = std::min(floor_deg, lowest);
    for (std::size_t v : in_l) {
      const CellMove m = move_into_middle_cell(t, v, max_lift, bound, min_edge, max_edge);
      if (!m.moved) continue;
      ++s.moved_into_cell;
      s.recut_tets += m.recut;
      s.max_cell_move = std::max(s.max_cell_move, m.h);
      s.moved_below_floor += m.below_floor;
      if (m.below_floor) s.min_dihedral_below_floor = std::min(s.min_dihedral_below_floor,
                                                               m.min_dihedral);
    }
  }
  s.left = in_l.empty() ? 0 : face_vertices_in_part_of_cells(t);
  return s;
}

CellFaceCut cut_at_cell_faces(PeriodicTets& t, double snap) {
  if (t.tets.size() != t.offsets.size())
    throw std::invalid_argument("cut_at_cell_faces: one offset set per tet");
  CellFaceCut stats;
  // Axis by axis, so that the vertices one split adds near the next axis's faces are snapped
  // too (else they leave pieces of almost no volume there).
  for (int axis = 0; axis < 3; ++axis) {
    if (snap > 0.0) snap_to_cell_faces(t, axis, snap, stats);
    Splitter(t, axis, stats).run();
  }
  return stats;
}

}  // namespace cmcsurf
