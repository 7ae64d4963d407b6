#include "mesh/tri_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace cmcsurf {

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double norm(const Vec3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

namespace {

double triangle_area(const TriMesh& m, const std::array<std::uint32_t, 3>& t) {
  return 0.5 * norm(cross(mesh_edge(m, t[0], t[1]), mesh_edge(m, t[0], t[2])));
}

// The sum of term(i), i < n, in fixed blocks added in order: the same bits for any thread
// count (a reduction's rounding depends on how the threads split the loop, and a part's
// level is solved on its volume, so its vertices moved with OMP_NUM_THREADS).
template <class Term>
double ordered_sum(std::size_t n, const Term& term) {
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<double> partial(blocks, 0.0);
#pragma omp parallel for schedule(static)
  for (std::size_t b = 0; b < blocks; ++b) {
    double s = 0.0;
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) s += term(i);
    partial[b] = s;
  }
  double s = 0.0;
  for (const double x : partial) s += x;
  return s;
}

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t(a) << 32) | std::uint64_t(b);
}

// True if the directed link edges b -> c around one vertex form a single cycle or path.
bool link_is_disk(std::vector<std::pair<std::uint32_t, std::uint32_t>>& link) {
  const std::size_t n = link.size();
  std::sort(link.begin(), link.end());
  for (std::size_t i = 1; i < n; ++i)
    if (link[i].first == link[i - 1].first) return false;  // two wedges start at b
  auto next = [&](std::uint32_t b) -> long {
    auto it = std::lower_bound(link.begin(), link.end(), std::make_pair(b, std::uint32_t(0)));
    return (it != link.end() && it->first == b) ? long(it - link.begin()) : -1;
  };
  // A path starts at a b that is no wedge's end; a cycle can start anywhere.
  std::size_t start = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool is_end = std::any_of(link.begin(), link.end(),
                                    [&](const auto& e) { return e.second == link[i].first; });
    if (!is_end) { start = i; break; }
  }
  std::size_t visited = 0;
  long cur = long(start);
  while (cur >= 0 && visited <= n) {
    ++visited;
    cur = next(link[std::size_t(cur)].second);
    if (cur == long(start)) break;
  }
  return visited == n;
}

}  // namespace

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// Ericson, Real-Time Collision Detection 5.1.5.
double point_triangle_distance2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  auto dist2 = [&](const Vec3& q) { const Vec3 d = sub(p, q); return dot(d, d); };
  auto at = [&](double v, double w) {
    return Vec3{a[0] + v * ab[0] + w * ac[0], a[1] + v * ab[1] + w * ac[1],
                a[2] + v * ab[2] + w * ac[2]};
  };
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return dot(ap, ap);
  const Vec3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return dist2(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return dist2(at(d1 / (d1 - d3), 0));
  const Vec3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return dist2(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return dist2(at(0, d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return dist2(at(1 - w, w));
  }
  const double denom = 1.0 / (va + vb + vc);
  return dist2(at(vb * denom, vc * denom));
}

Vec3 mesh_edge(const TriMesh& m, std::uint32_t a, std::uint32_t b) {
  Vec3 d;
  for (int c = 0; c < 3; ++c) {
    d[c] = m.vertices[b][c] - m.vertices[a][c];
    if (m.period[c] > 0) d[c] -= m.period[c] * std::nearbyint(d[c] / m.period[c]);
  }
  return d;
}

double mesh_area(const TriMesh& m) {
  return ordered_sum(m.triangles.size(),
                     [&](std::size_t t) { return triangle_area(m, m.triangles[t]); });
}

double mesh_volume(const TriMesh& m) {
  // Sum of signed tetrahedra (origin, a, b, c) about the bounding-box centre (less round-off).
  Vec3 o{0, 0, 0};
  if (!m.vertices.empty()) {
    Vec3 lo = m.vertices[0], hi = m.vertices[0];
    for (const Vec3& v : m.vertices)
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], v[c]), hi[c] = std::max(hi[c], v[c]);
    for (int c = 0; c < 3; ++c) o[c] = 0.5 * (lo[c] + hi[c]);
  }
  const double s = ordered_sum(m.triangles.size(), [&](std::size_t t) {
    const auto& tri = m.triangles[t];
    Vec3 p[3];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) p[k][c] = m.vertices[tri[k]][c] - o[c];
    const Vec3 bc = cross(p[1], p[2]);
    return p[0][0] * bc[0] + p[0][1] * bc[1] + p[0][2] * bc[2];
  });
  return s / 6.0;
}

MeshStats bounding_box(const TriMesh& m) {
  MeshStats box;
  if (m.vertices.empty()) return box;
  box.min = box.max = m.vertices[0];
  for (const Vec3& v : m.vertices)
    for (int c = 0; c < 3; ++c)
      box.min[c] = std::min(box.min[c], v[c]), box.max[c] = std::max(box.max[c], v[c]);
  return box;
}

MeshStats analyze_mesh(const TriMesh& m) {
  MeshStats st;
  st.vertices = m.vertices.size();
  st.triangles = m.triangles.size();
  st.area = mesh_area(m);
  const bool periodic = m.period[0] > 0 || m.period[1] > 0 || m.period[2] > 0;
  st.volume = periodic ? 0.0 : mesh_volume(m);
  if (!m.vertices.empty()) {
    st.min = st.max = m.vertices[0];
    for (const Vec3& v : m.vertices)
      for (int c = 0; c < 3; ++c)
        st.min[c] = std::min(st.min[c], v[c]), st.max[c] = std::max(st.max[c], v[c]);
  }

  // Directed edges, sorted: an undirected edge {a, b} is used n_ab + n_ba times.
  std::vector<std::uint64_t> directed;
  directed.reserve(3 * m.triangles.size());
  std::vector<char> used(m.vertices.size(), 0);
  for (const auto& t : m.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0] || triangle_area(m, t) == 0.0)
      ++st.degenerate_triangles;
    for (int k = 0; k < 3; ++k) {
      directed.push_back(edge_key(t[k], t[(k + 1) % 3]));
      used[t[k]] = 1;
    }
  }
  st.unused_vertices = std::size_t(std::count(used.begin(), used.end(), 0));
  std::sort(directed.begin(), directed.end());
  auto count = [&](std::uint64_t key) {
    auto r = std::equal_range(directed.begin(), directed.end(), key);
    return std::size_t(r.second - r.first);
  };
  for (std::size_t i = 0; i < directed.size();) {
    std::size_t j = i;
    while (j < directed.size() && directed[j] == directed[i]) ++j;
    const std::uint32_t a = std::uint32_t(directed[i] >> 32), b = std::uint32_t(directed[i]);
    const std::size_t n_ab = j - i, n_ba = count(edge_key(b, a));
    if (n_ab > 1) ++st.misoriented_edges;
    // Count each undirected edge once: at its (min, max) key, or at (max, min) if alone.
    if (a < b || n_ba == 0) {
      ++st.edges;
      if (n_ab + n_ba == 1) ++st.boundary_edges;
      if (n_ab + n_ba > 2) ++st.nonmanifold_edges;
    }
    i = j;
  }
  std::vector<std::uint64_t>().swap(directed);

  // Duplicate triangles: same sorted vertex triple.
  std::vector<std::array<std::uint32_t, 3>> sorted(m.triangles);
  for (auto& t : sorted) std::sort(t.begin(), t.end());
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i] == sorted[i - 1]) ++st.duplicate_triangles;
  std::vector<std::array<std::uint32_t, 3>>().swap(sorted);

  // Vertex links: wedges (v; b -> c) grouped by v.
  std::vector<std::array<std::uint32_t, 3>> wedges;
  wedges.reserve(3 * m.triangles.size());
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) wedges.push_back({t[k], t[(k + 1) % 3], t[(k + 2) % 3]});
  std::sort(wedges.begin(), wedges.end());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> link;
  for (std::size_t i = 0; i < wedges.size();) {
    link.clear();
    std::size_t j = i;
    for (; j < wedges.size() && wedges[j][0] == wedges[i][0]; ++j)
      link.emplace_back(wedges[j][1], wedges[j][2]);
    if (!link_is_disk(link)) ++st.nonmanifold_vertices;
    i = j;
  }

  st.euler = long(st.vertices - st.unused_vertices) - long(st.edges) + long(st.triangles);
  return st;
}

}  // namespace cmcsurf
