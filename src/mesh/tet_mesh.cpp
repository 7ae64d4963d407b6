#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>
#include <numbers>
#include <stdexcept>
#include <unordered_map>

#include "mesh/union_find.h"

namespace cmcsurf {

namespace {

using Image = std::array<int, 3>;  // whole periods added to a torus vertex

struct UnionFind {
  std::vector<std::int64_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) {
    std::iota(parent.begin(), parent.end(), std::int64_t(0));
  }
  std::int64_t find(std::int64_t a) { return find_root(parent, a); }
  void join(std::int64_t a, std::int64_t b) { parent[find(a)] = find(b); }
};

struct FaceKey {
  std::array<std::int64_t, 3> v;
  bool operator==(const FaceKey& o) const { return v == o.v; }
};
struct FaceHash {
  std::size_t operator()(const FaceKey& f) const {
    std::size_t h = 1469598103934665603ull;
    for (auto x : f.v) h = (h ^ std::size_t(x)) * 1099511628211ull;
    return h;
  }
};
FaceKey sorted_face(std::int64_t a, std::int64_t b, std::int64_t c) {
  FaceKey f{{a, b, c}};
  std::sort(f.v.begin(), f.v.end());
  return f;
}

// The box-face measures of TetMeshStats over the boundary faces that `periodic` accepts.
template <class Periodic>
void box_faces(const TetMesh& m, const std::vector<FaceKey>& boundary, Periodic periodic,
               TetMeshStats& s) {
  // Exact comparisons: nodes on a plane are written as 0 or whole periods, not computed.
  auto on = [&](std::int64_t v, int a, int side) {
    return m.nodes[v][a] == (side ? m.period[a] : 0.0);
  };
  for (std::size_t v = 0; v < m.nodes.size(); ++v)
    for (int a = 0; a < 3; ++a) {
      s.plane_nodes[2 * a] += on(std::int64_t(v), a, 0);
      s.plane_nodes[2 * a + 1] += on(std::int64_t(v), a, 1);
      s.nodes_outside_box += m.nodes[v][a] < 0.0 || m.nodes[v][a] > m.period[a];
    }
  // A node on a plane is paired across it when its group (a master and its slaves, the images
  // of one point) holds the node one period away along that axis alone: the partner a user
  // tying the plane by coordinates looks for.
  std::unordered_map<std::int64_t, std::vector<std::int64_t>> groups;
  for (const PeriodicPair& p : m.pairs) {
    auto& g = groups[p.master];
    if (g.empty()) g.push_back(p.master);
    g.push_back(p.slave);
  }
  std::vector<char> in_group(m.nodes.size(), 0);
  for (const auto& [master, g] : groups)
    for (std::int64_t v : g) {
      in_group[std::size_t(v)] = 1;
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          if (!on(v, a, side)) continue;
          bool found = false;
          for (std::int64_t w : g)
            found = found || (on(w, a, 1 - side) && m.nodes[w][(a + 1) % 3] ==
                                                        m.nodes[v][(a + 1) % 3] &&
                              m.nodes[w][(a + 2) % 3] == m.nodes[v][(a + 2) % 3]);
          s.unpaired_plane_nodes += !found;
        }
    }
  for (std::size_t v = 0; v < m.nodes.size(); ++v)
    for (int a = 0; a < 3 && !in_group[v]; ++a)
      s.unpaired_plane_nodes += on(std::int64_t(v), a, 0) + on(std::int64_t(v), a, 1);
  // Per plane, each face as its nodes' two other coordinates, sorted: opposite planes must hold
  // the same list.
  using Flat = std::array<std::array<double, 2>, 3>;
  std::array<std::vector<Flat>, 6> on_plane;
  for (const FaceKey& f : boundary) {
    if (!periodic(f)) continue;
    int plane = -1;
    for (int a = 0; a < 3 && plane < 0; ++a)
      for (int side = 0; side < 2 && plane < 0; ++side)
        if (on(f.v[0], a, side) && on(f.v[1], a, side) && on(f.v[2], a, side))
          plane = 2 * a + side;
    if (plane < 0) {
      ++s.periodic_faces_off_plane;
      continue;
    }
    const int a = plane / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    Flat x;
    for (int k = 0; k < 3; ++k) x[k] = {m.nodes[f.v[k]][b], m.nodes[f.v[k]][c]};
    std::sort(x.begin(), x.end());
    on_plane[std::size_t(plane)].push_back(x);
  }
  for (int a = 0; a < 3; ++a) {
    auto& lo = on_plane[std::size_t(2 * a)];
    auto& hi = on_plane[std::size_t(2 * a + 1)];
    std::sort(lo.begin(), lo.end());
    std::sort(hi.begin(), hi.end());
    std::vector<Flat> diff;
    std::set_symmetric_difference(lo.begin(), lo.end(), hi.begin(), hi.end(),
                                  std::back_inserter(diff));
    s.unmirrored_faces += diff.size();
  }
}

}  // namespace

std::vector<TorusFace> torus_boundary_faces(const PeriodicTets& t) {
  std::vector<TorusFace> faces;
  faces.reserve(4 * t.tets.size());
  for (std::size_t i = 0; i < t.tets.size(); ++i)
    for (int skip = 0; skip < 4; ++skip) {
      TorusFace f;
      f.tet = i, f.skip = skip;
      int k = 0;
      for (int c = 0; c < 4; ++c)
        if (c != skip)
          f.corners[std::size_t(k++)] = {
              t.tets[i][c], {t.offsets[i][c][0], t.offsets[i][c][1], t.offsets[i][c][2]}};
      std::sort(f.corners.begin(), f.corners.end());
      const Image base = f.corners[0].second;  // translate so the first corner has offset 0
      for (auto& [v, w] : f.corners)
        for (int a = 0; a < 3; ++a) w[a] -= base[a];
      faces.push_back(f);
    }
  const auto by_corners = [](const TorusFace& a, const TorusFace& b) {
    return a.corners < b.corners;
  };
  std::sort(faces.begin(), faces.end(), by_corners);
  std::vector<TorusFace> boundary;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j].corners == faces[i].corners) ++j;
    if (j - i == 1) boundary.push_back(faces[i]);
    i = j;
  }
  return boundary;
}

double tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return dot(sub(b, a), cross(sub(c, a), sub(d, a))) / 6.0;
}

TetMesh unfold_periodic_tets(const PeriodicTets& torus, const std::array<int, 3>& tiles,
                             double cell_size) {
  if (torus.tets.size() != torus.offsets.size())
    throw std::invalid_argument("unfold_periodic_tets: one offset set per tet");
  for (int c = 0; c < 3; ++c)
    if (tiles[c] < 1 || tiles[c] > 100)
      throw std::invalid_argument("unfold_periodic_tets: tiles must be 1..100 per axis");
  TetMesh m;
  for (int c = 0; c < 3; ++c) m.period[c] = tiles[c] * cell_size;
  // Each torus vertex's images in use and their node numbers; found by a hash of (vertex,
  // image), since a vertex has hundreds of images in a large tiling.
  std::vector<std::vector<std::pair<Image, std::int64_t>>> images(torus.vertices.size());
  std::unordered_map<std::uint64_t, std::int64_t> node_ids;
  auto node_of = [&](std::int32_t v, const Image& w) {
    // 8 bits per image component (a tet's corners lie within a period or two of the block).
    std::uint64_t key = std::uint64_t(v);
    for (int a = 0; a < 3; ++a) key = (key << 8) | (std::uint64_t(w[a] + 128) & 0xff);
    const auto [it, fresh] = node_ids.try_emplace(key, std::int64_t(m.nodes.size()));
    if (!fresh) return it->second;
    const std::int64_t id = it->second;
    const Vec3& p = torus.vertices[std::size_t(v)];
    m.nodes.push_back({(p[0] + w[0]) * cell_size, (p[1] + w[1]) * cell_size,
                       (p[2] + w[2]) * cell_size});
    images[std::size_t(v)].push_back({w, id});
    return id;
  };
  const std::size_t cells = std::size_t(tiles[0]) * tiles[1] * tiles[2];
  m.tets.reserve(torus.tets.size() * cells);
  std::vector<std::array<Image, 4>> placed(torus.tets.size());
  for (std::size_t t = 0; t < torus.tets.size(); ++t) {
    Vec3 centroid{0, 0, 0};
    for (int c = 0; c < 4; ++c)
      for (int a = 0; a < 3; ++a)
        centroid[a] += 0.25 * (torus.vertices[std::size_t(torus.tets[t][c])][a] +
                               torus.offsets[t][c][a]);
    for (int c = 0; c < 4; ++c)
      for (int a = 0; a < 3; ++a)
        placed[t][c][a] = torus.offsets[t][c][a] - int(std::floor(centroid[a]));
  }
  for (int tz = 0; tz < tiles[2]; ++tz)
    for (int ty = 0; ty < tiles[1]; ++ty)
      for (int tx = 0; tx < tiles[0]; ++tx)
        for (std::size_t t = 0; t < torus.tets.size(); ++t) {
          std::array<std::int64_t, 4> tet;
          for (int c = 0; c < 4; ++c) {
            const Image& w = placed[t][c];
            tet[c] = node_of(torus.tets[t][c], {w[0] + tx, w[1] + ty, w[2] + tz});
          }
          m.tets.push_back(tet);
        }
  // Images one block period apart are the same point of the periodic solid: the one nearest
  // the block is the master.
  auto outside = [&](std::int64_t id) {
    double d = 0.0;
    for (int a = 0; a < 3; ++a)
      d += std::max(0.0, -m.nodes[id][a]) + std::max(0.0, m.nodes[id][a] - m.period[a]);
    return d;
  };
  auto wrapped = [&](const Image& w) {
    Image r;
    for (int a = 0; a < 3; ++a) r[a] = ((w[a] % tiles[a]) + tiles[a]) % tiles[a];
    return r;
  };
  for (auto& list : images) {
    // Sorted by the image modulo the block, so that each point's images are adjacent.
    std::sort(list.begin(), list.end(), [&](const auto& x, const auto& y) {
      return std::pair(wrapped(x.first), x.first) < std::pair(wrapped(y.first), y.first);
    });
    for (std::size_t i = 0; i < list.size();) {
      std::vector<std::size_t> group;
      const Image key = wrapped(list[i].first);
      while (i < list.size() && wrapped(list[i].first) == key) group.push_back(i++);
      if (group.size() < 2) continue;
      const std::size_t master = *std::min_element(
          group.begin(), group.end(), [&](std::size_t a, std::size_t b) {
            const double oa = outside(list[a].second), ob = outside(list[b].second);
            return oa != ob ? oa < ob : list[a].first < list[b].first;
          });
      for (std::size_t j : group) {
        if (j == master) continue;
        PeriodicPair p;
        p.slave = list[j].second;
        p.master = list[master].second;
        for (int a = 0; a < 3; ++a)
          p.translation[a] = (list[j].first[a] - list[master].first[a]) * cell_size;
        m.pairs.push_back(p);
      }
    }
  }
  std::sort(m.pairs.begin(), m.pairs.end(),
            [](const PeriodicPair& a, const PeriodicPair& b) { return a.slave < b.slave; });
  const std::size_t boundary = torus_boundary_faces(torus).size();
  m.surface_faces = boundary * cells;
  return m;
}

TetMeshStats analyze_tet_mesh(const TetMesh& m, double size_min, double size_max) {
  TetMeshStats s;
  s.size_min = size_min, s.size_max = size_max;
  s.nodes = m.nodes.size();
  s.tets = m.tets.size();
  if (m.tets.empty()) return s;
  // Edges, shortest first per tet for the radius-edge ratio.
  std::vector<std::pair<std::int64_t, std::int64_t>> edges;
  edges.reserve(6 * m.tets.size());
  double min_dihedral = 180.0, max_dihedral = 0.0, re_sum = 0.0;
  constexpr int kEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (const auto& t : m.tets) {
    const Vec3 &a = m.nodes[t[0]], &b = m.nodes[t[1]], &c = m.nodes[t[2]], &d = m.nodes[t[3]];
    const std::array<Vec3, 4> p{a, b, c, d};
    const double v = tet_volume(a, b, c, d);
    s.volume += v;
    double lmin = INFINITY, lmax = 0.0;
    for (const auto& e : kEdge) {
      const double l = norm(sub(p[e[1]], p[e[0]]));
      lmin = std::min(lmin, l), lmax = std::max(lmax, l);
      edges.push_back(std::minmax(t[e[0]], t[e[1]]));
    }
    if (v < 0) ++s.inverted;
    if (std::abs(v) <= 1e-10 * lmax * lmax * lmax) {
      ++s.degenerate;
      continue;
    }
    // Outward normal of the face opposite each corner.
    std::array<Vec3, 4> n;
    for (int k = 0; k < 4; ++k) {
      const Vec3 &q0 = p[(k + 1) % 4], &q1 = p[(k + 2) % 4], &q2 = p[(k + 3) % 4];
      Vec3 nk = cross(sub(q1, q0), sub(q2, q0));
      if (dot(nk, sub(p[k], q0)) > 0) nk = {-nk[0], -nk[1], -nk[2]};
      n[k] = nk;
    }
    double tet_min = 180.0;
    for (const auto& e : kEdge) {
      // The two faces meeting at edge (e0, e1) are those opposite the other two corners.
      int o[2], k = 0;
      for (int q = 0; q < 4; ++q)
        if (q != e[0] && q != e[1]) o[k++] = q;
      const double cosine =
          std::clamp(dot(n[o[0]], n[o[1]]) / (norm(n[o[0]]) * norm(n[o[1]])), -1.0, 1.0);
      const double angle = 180.0 - std::acos(cosine) * 180.0 / std::numbers::pi;
      tet_min = std::min(tet_min, angle);
      max_dihedral = std::max(max_dihedral, angle);
    }
    min_dihedral = std::min(min_dihedral, tet_min);
    ++s.dihedral_histogram[std::min<std::size_t>(17, std::size_t(tet_min / 10.0))];
    // Circumcentre relative to a.
    const Vec3 B = sub(b, a), C = sub(c, a), D = sub(d, a);
    const Vec3 cd = cross(C, D), db = cross(D, B), bc = cross(B, C);
    const double den = 2.0 * dot(B, cd);
    Vec3 o{};
    for (int q = 0; q < 3; ++q)
      o[q] = (dot(B, B) * cd[q] + dot(C, C) * db[q] + dot(D, D) * bc[q]) / den;
    const double re = norm(o) / lmin;
    s.max_radius_edge = std::max(s.max_radius_edge, re);
    re_sum += re;
  }
  const std::size_t good = s.tets - s.degenerate;
  s.min_dihedral_deg = good ? min_dihedral : 0.0;
  s.max_dihedral_deg = max_dihedral;
  s.mean_radius_edge = good ? re_sum / double(good) : 0.0;
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  s.edges = edges.size();
  s.min_edge = INFINITY;
  double sum = 0.0;
  std::vector<std::pair<std::int64_t, std::int64_t>> short_edges;
  for (const auto& [i, j] : edges) {
    const double l = norm(sub(m.nodes[j], m.nodes[i]));
    s.min_edge = std::min(s.min_edge, l), s.max_edge = std::max(s.max_edge, l);
    sum += l;
    if (size_min > 0 && l < size_min) short_edges.push_back({i, j});
    if (size_max > 0 && l > size_max) ++s.edges_above_max;
  }
  s.mean_edge = sum / double(edges.size());
  // Connectivity: tets joined through shared nodes, then across the pairs.
  UnionFind uf(m.nodes.size());
  for (const auto& t : m.tets)
    for (int c = 1; c < 4; ++c) uf.join(t[0], t[c]);
  std::vector<char> used(m.nodes.size(), 0);
  for (const auto& t : m.tets)
    for (auto v : t) used[v] = 1;
  auto count_components = [&]() {
    std::size_t r = 0;
    for (std::size_t i = 0; i < m.nodes.size(); ++i)
      r += used[i] && uf.find(std::int64_t(i)) == std::int64_t(i);
    return r;
  };
  s.components = count_components();
  // Boundary faces; a periodic face has a twin whose nodes are the same up to the pairs.
  std::vector<std::int64_t> rep(m.nodes.size());
  std::iota(rep.begin(), rep.end(), std::int64_t(0));
  std::vector<char> paired(m.nodes.size(), 0);
  const double scale = std::max({m.period[0], m.period[1], m.period[2], 1e-300});
  for (const auto& p : m.pairs) {
    rep[p.slave] = p.master;
    paired[p.slave] = paired[p.master] = 1;
    double mis = 0.0;
    for (int a = 0; a < 3; ++a)
      mis = std::max(mis,
                     std::abs(m.nodes[p.slave][a] - m.nodes[p.master][a] - p.translation[a]));
    s.pair_mismatch = std::max(s.pair_mismatch, mis / scale);
  }
  std::unordered_map<FaceKey, int, FaceHash> count;
  count.reserve(4 * m.tets.size());
  for (const auto& t : m.tets)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<std::int64_t, 3> f;
      int k = 0;
      for (int c = 0; c < 4; ++c)
        if (c != skip) f[k++] = t[c];
      ++count[sorted_face(f[0], f[1], f[2])];
    }
  std::unordered_map<FaceKey, int, FaceHash> periodic;
  std::vector<FaceKey> boundary;
  for (const auto& [f, n] : count)
    if (n == 1) {
      boundary.push_back(f);
      ++periodic[sorted_face(rep[f.v[0]], rep[f.v[1]], rep[f.v[2]])];
    }
  // Where the short edges are: 1 on the solid's surface, 2 on the cut, 3 both.
  std::vector<char> place(m.nodes.size(), 0);
  for (const auto& f : boundary) {
    if (periodic[sorted_face(rep[f.v[0]], rep[f.v[1]], rep[f.v[2]])] < 2) {
      for (auto v : f.v) place[v] |= 1;
      continue;
    }
    ++s.periodic_faces;
    for (auto v : f.v) s.unpaired_nodes += !paired[v], place[v] |= 2;
  }
  s.edges_below_min = short_edges.size();
  // Exact: nodes on a plane are written as 0 or whole periods.
  auto on_box_edge = [&](std::int64_t v) {
    int planes = 0;
    for (int a = 0; a < 3; ++a)
      planes += m.nodes[std::size_t(v)][a] == 0.0 || m.nodes[std::size_t(v)][a] == m.period[a];
    return planes >= 2;
  };
  for (const auto& [i, j] : short_edges) {
    s.edges_below_min_box_edge += on_box_edge(i) || on_box_edge(j);
    const int both = place[i] & place[j];
    if (both & 2)
      ++s.edges_below_min_cut;
    else if (both & 1)
      ++s.edges_below_min_surface;
  }
  box_faces(m, boundary, [&](const FaceKey& f) {
    const auto it = periodic.find(sorted_face(rep[f.v[0]], rep[f.v[1]], rep[f.v[2]]));
    return it != periodic.end() && it->second >= 2;
  }, s);
  const std::size_t rest = boundary.size() - s.periodic_faces;
  s.surface_faces = std::min(rest, m.surface_faces);
  s.unmatched_faces = rest - s.surface_faces;
  for (const auto& p : m.pairs) uf.join(p.slave, p.master);
  s.components_periodic = count_components();  // paired nodes are one point of the solid
  return s;
}

nlohmann::json dihedral_histogram_json(const std::array<std::size_t, 18>& histogram) {
  nlohmann::json hist = nlohmann::json::array();
  for (std::size_t b = 0; b < histogram.size(); ++b)
    if (histogram[b])
      hist.push_back({{"from_deg", 10 * b}, {"to_deg", 10 * (b + 1)}, {"tets", histogram[b]}});
  return hist;
}

nlohmann::json tet_mesh_stats_json(const TetMeshStats& s, const std::string& units) {
  const nlohmann::json hist = dihedral_histogram_json(s.dihedral_histogram);
  // Whether the shortest edge meets --size-min: null when none was asked for.
  const nlohmann::json size_min_met =
      s.size_min > 0 ? nlohmann::json(s.edges_below_min == 0) : nlohmann::json();
  return {
      {"nodes", s.nodes},
      {"tets", s.tets},
      {"edges", s.edges},
      {"volume", s.volume},
      {"volume_units", units + "^3"},
      {"quality",
       {{"min_dihedral_deg", s.min_dihedral_deg},
        {"max_dihedral_deg", s.max_dihedral_deg},
        {"max_radius_edge_ratio", s.max_radius_edge},
        {"mean_radius_edge_ratio", s.mean_radius_edge},
        {"min_dihedral_histogram", hist},
        {"note", "radius-edge ratio: circumradius / shortest edge (regular tet: 0.612)"}}},
      {"edge_length",
       {{"min", s.min_edge},
        {"max", s.max_edge},
        {"mean", s.mean_edge},
        {"size_min", s.size_min},
        {"size_min_met", size_min_met},
        {"below_size_min", s.edges_below_min},
        {"below_size_min_on_cut", s.edges_below_min_cut},
        {"below_size_min_on_surface", s.edges_below_min_surface},
        {"below_size_min_at_box_edges", s.edges_below_min_box_edge},
        {"above_size_max", s.edges_above_max},
        {"units", units}}},
      {"checks",
       {{"inverted_tets", s.inverted},
        {"degenerate_tets", s.degenerate},
        {"components_in_block", s.components},
        {"components_periodic", s.components_periodic},
        {"surface_faces", s.surface_faces},
        {"periodic_faces", s.periodic_faces},
        {"unmatched_boundary_faces", s.unmatched_faces},
        {"unpaired_nodes", s.unpaired_nodes},
        {"unpaired_plane_nodes", s.unpaired_plane_nodes},
        {"pair_mismatch", s.pair_mismatch},
        {"periodic_faces_off_plane", s.periodic_faces_off_plane},
        {"nodes_outside_box", s.nodes_outside_box},
        {"unmirrored_faces", s.unmirrored_faces}}},
      {"box_face_nodes",
       {{"x_min", s.plane_nodes[0]},
        {"x_max", s.plane_nodes[1]},
        {"y_min", s.plane_nodes[2]},
        {"y_max", s.plane_nodes[3]},
        {"z_min", s.plane_nodes[4]},
        {"z_max", s.plane_nodes[5]},
        {"note", "nodes on each plane of the box [0, period]; edge and corner nodes count on "
                 "each of their planes"}}}};
}

}  // namespace cmcsurf
