#include "mesh/marching_tets.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "grid/kuhn.h"

namespace cmcsurf {

namespace {

constexpr auto& kCorner = kCubeCorner;
constexpr auto& kTet = kKuhnTets;

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

struct Extractor {
  const NodeLattice& lat;
  double iso;
  int nx, ny, nz;
  TriMesh mesh;
  // Vertex index of each edge, per node layer: [(j * nx + i) * 7 + dir], dir = dx + 2dy + 4dz - 1.
  std::vector<std::uint32_t> edges_lo, edges_hi, edges_first;
  std::vector<double> values_lo, values_hi;

  Extractor(const NodeLattice& l, double v)
      : lat(l), iso(v), nx(l.nodes[0]), ny(l.nodes[1]), nz(l.nodes[2]) {}

  int wrap(int i, int n) const { return i >= n ? i - n : i; }

  bool is_pad(int i, int j, int k) const {
    return lat.pad_outside &&
           (i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1);
  }
  // Where the edge from node (i, j, k) to (i + dx, j + dy, k + dz) crosses iso.
  double edge_fraction(int i, int j, int k, int dx, int dy, int dz, double v0, double v1) const {
    if (is_pad(i, j, k) || is_pad(i + dx, j + dy, k + dz)) return 0.5;  // on the box face
    return std::clamp((iso - v0) / (v1 - v0), kMinEdgeFraction, 1.0 - kMinEdgeFraction);
  }

  std::uint32_t vertex(int i, int j, int k, const int* c0, const int* c1, double v0, double v1) {
    // Lower node of the edge (corner c0 <= c1 componentwise in a Kuhn tetrahedron).
    const int li = wrap(i + c0[0], nx), lj = wrap(j + c0[1], ny);
    const bool hi = c0[2] == 1;
    std::vector<std::uint32_t>& layer = hi ? edges_hi : edges_lo;
    const int dir = (c1[0] - c0[0]) + 2 * (c1[1] - c0[1]) + 4 * (c1[2] - c0[2]) - 1;
    std::uint32_t& slot = layer[(std::size_t(lj) * nx + li) * 7 + dir];
    if (slot != kNone) return slot;
    const double t = edge_fraction(i + c0[0], j + c0[1], k + c0[2], c1[0] - c0[0], c1[1] - c0[1],
                                   c1[2] - c0[2], v0, v1);
    const int lk = hi ? wrap(k + 1, nz) : k;
    const int node[3] = {li, lj, lk};
    Vec3 p;
    for (int c = 0; c < 3; ++c)
      p[c] = lat.origin[c] + (node[c] + t * (c1[c] - c0[c])) * lat.spacing[c];
    if (mesh.vertices.size() >= kNone) throw std::runtime_error("mesh: more than 2^32 vertices");
    slot = std::uint32_t(mesh.vertices.size());
    mesh.vertices.push_back(p);
    return slot;
  }

  void emit(std::uint32_t a, std::uint32_t b, std::uint32_t c, const Vec3& pa, const Vec3& pb,
            const Vec3& pc, const Vec3& towards_inside) {
    const Vec3 u{pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    const Vec3 w{pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
    const Vec3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double s = n[0] * towards_inside[0] + n[1] * towards_inside[1] + n[2] * towards_inside[2];
    if (s > 0) std::swap(b, c);
    mesh.triangles.push_back({a, b, c});
  }

  void cube(int i, int j, int k, const double* val) {
    bool any_in = false, any_out = false;
    for (int c = 0; c < 8; ++c) (val[c] > iso ? any_in : any_out) = true;
    if (!any_in || !any_out) return;
    for (const auto& tet : kTet) {
      int in[4], out[4], n_in = 0, n_out = 0;
      for (int q = 0; q < 4; ++q) (val[tet[q]] > iso ? in[n_in++] : out[n_out++]) = tet[q];
      if (n_in == 0 || n_out == 0) continue;
      // Direction from the outside corners' centroid to the inside corners' centroid.
      Vec3 g{0, 0, 0};
      for (int c = 0; c < 3; ++c) {
        for (int q = 0; q < n_in; ++q) g[c] += kCorner[in[q]][c] * lat.spacing[c] / n_in;
        for (int q = 0; q < n_out; ++q) g[c] -= kCorner[out[q]][c] * lat.spacing[c] / n_out;
      }
      auto on_edge = [&](int a, int b, Vec3& local) {
        if (a > b) std::swap(a, b);  // corner order is componentwise order within a tet
        const std::uint32_t v = vertex(i, j, k, kCorner[a], kCorner[b], val[a], val[b]);
        const double t = edge_fraction(i + kCorner[a][0], j + kCorner[a][1], k + kCorner[a][2],
                                       kCorner[b][0] - kCorner[a][0], kCorner[b][1] - kCorner[a][1],
                                       kCorner[b][2] - kCorner[a][2], val[a], val[b]);
        for (int c = 0; c < 3; ++c)
          local[c] = (kCorner[a][c] + t * (kCorner[b][c] - kCorner[a][c])) * lat.spacing[c];
        return v;
      };
      Vec3 p0, p1, p2, p3;
      if (n_in == 1 || n_out == 1) {
        const int a = n_in == 1 ? in[0] : out[0];
        const int* others = n_in == 1 ? out : in;
        const std::uint32_t v0 = on_edge(a, others[0], p0), v1 = on_edge(a, others[1], p1),
                            v2 = on_edge(a, others[2], p2);
        emit(v0, v1, v2, p0, p1, p2, g);
      } else {  // quad on edges ac, ad, bd, bc
        const int a = in[0], b = in[1], c = out[0], d = out[1];
        const std::uint32_t v0 = on_edge(a, c, p0), v1 = on_edge(a, d, p1),
                            v2 = on_edge(b, d, p2), v3 = on_edge(b, c, p3);
        emit(v0, v1, v2, p0, p1, p2, g);
        emit(v0, v2, v3, p0, p2, p3, g);
      }
    }
  }

  TriMesh run() {
    if (nx < 2 || ny < 2 || nz < 2)
      throw std::invalid_argument("mesh: lattice needs >= 2 nodes per axis");
    const std::size_t layer_nodes = std::size_t(nx) * ny;
    edges_lo.assign(layer_nodes * 7, kNone);
    edges_hi.assign(layer_nodes * 7, kNone);
    values_lo.resize(layer_nodes);
    values_hi.resize(layer_nodes);
    const int cubes_x = lat.periodic ? nx : nx - 1, cubes_y = lat.periodic ? ny : ny - 1;
    const int cubes_z = lat.periodic ? nz : nz - 1;
    if (lat.periodic && lat.pad_outside)
      throw std::invalid_argument("mesh: a periodic lattice has no pad");
    auto fill = [&](int k, std::vector<double>& v) {
      lat.layer(k, v.data());
      if (!lat.pad_outside) return;
      const double outside = std::numeric_limits<double>::lowest();
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          if (is_pad(i, j, k)) v[std::size_t(j) * nx + i] = outside;
    };
    fill(0, values_lo);
    for (int k = 0; k < cubes_z; ++k) {
      const bool wrap_top = lat.periodic && k == nz - 1;
      if (wrap_top) {
        edges_hi = edges_first;
        fill(0, values_hi);
      } else {
        fill(k + 1, values_hi);
      }
      double val[8];
      for (int j = 0; j < cubes_y; ++j)
        for (int i = 0; i < cubes_x; ++i) {
          for (int c = 0; c < 8; ++c) {
            const int ii = wrap(i + kCorner[c][0], nx), jj = wrap(j + kCorner[c][1], ny);
            val[c] = (kCorner[c][2] ? values_hi : values_lo)[std::size_t(jj) * nx + ii];
          }
          cube(i, j, k, val);
        }
      if (lat.periodic && k == 0) edges_first = edges_lo;
      std::swap(edges_lo, edges_hi);
      std::fill(edges_hi.begin(), edges_hi.end(), kNone);
      std::swap(values_lo, values_hi);
    }
    if (lat.periodic)
      for (int c = 0; c < 3; ++c) mesh.period[c] = lat.nodes[c] * lat.spacing[c];
    return std::move(mesh);
  }
};

}  // namespace

TriMesh extract_isosurface(const NodeLattice& lattice, double iso) {
  Extractor e(lattice, iso);
  return e.run();
}

}  // namespace cmcsurf
