#include "mesh/part.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "common/wall_clock.h"
#include "mesh/marching_tets.h"
#include "mesh/union_find.h"
#include "parallel/first_exception.h"

namespace cmcsurf {

namespace {

constexpr std::uint32_t kNoRoot = std::numeric_limits<std::uint32_t>::max();
constexpr float kRemoved = std::numeric_limits<float>::lowest();
constexpr int kMaxNodesPerAxis = 8192;

// The 7 edge directions of the Kuhn tetrahedra from a node to a later one (grid/kuhn.h: every
// edge joins corners in componentwise order, so its direction is in {0, 1}^3 \ 0).
constexpr int kKuhnEdges[7][3] = {{1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1},
                                  {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};

// Union-find over the nodes where member(node) holds; returns each node's root (kNoRoot for the
// others).
std::vector<std::uint32_t> label_components(const PartLattice& lat,
                                            const std::function<bool(std::size_t)>& member) {
  const auto& n = lat.nodes;
  std::vector<std::uint32_t> parent(lat.count(), kNoRoot);
  for (std::size_t id = 0; id < parent.size(); ++id)
    if (member(id)) parent[id] = std::uint32_t(id);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t id = lat.index(i, j, k);
        if (parent[id] == kNoRoot) continue;
        for (const auto& e : kKuhnEdges) {
          const int ii = i + e[0], jj = j + e[1], kk = k + e[2];
          if (ii >= n[0] || jj >= n[1] || kk >= n[2]) continue;
          const std::size_t nb = lat.index(ii, jj, kk);
          if (parent[nb] == kNoRoot) continue;
          const std::uint32_t a = find_root(parent, std::uint32_t(id));
          const std::uint32_t b = find_root(parent, std::uint32_t(nb));
          if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
      }
  for (std::size_t id = 0; id < parent.size(); ++id)
    if (parent[id] != kNoRoot) parent[id] = find_root(parent, std::uint32_t(id));
  return parent;
}

struct ComponentBox {
  std::size_t nodes = 0;
  std::array<int, 3> lo{kMaxNodesPerAxis, kMaxNodesPerAxis, kMaxNodesPerAxis}, hi{-1, -1, -1};
  unsigned faces = 0;  // bit 2c: touches face c = 0; bit 2c + 1: touches the far face
};

std::map<std::uint32_t, ComponentBox> component_boxes(const PartLattice& lat,
                                                      const std::vector<std::uint32_t>& root) {
  std::map<std::uint32_t, ComponentBox> boxes;
  const auto& n = lat.nodes;
  std::uint32_t last = kNoRoot;
  ComponentBox* b = nullptr;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::uint32_t r = root[lat.index(i, j, k)];
        if (r == kNoRoot) continue;
        if (r != last) b = &boxes[r], last = r;
        ++b->nodes;
        const int at[3] = {i, j, k};
        for (int c = 0; c < 3; ++c) {
          b->lo[c] = std::min(b->lo[c], at[c]);
          b->hi[c] = std::max(b->hi[c], at[c]);
          if (at[c] == 0) b->faces |= 1u << (2 * c);
          if (at[c] == n[c] - 1) b->faces |= 1u << (2 * c + 1);
        }
      }
  return boxes;
}

// The mesh over the window of nodes lo..hi per axis in part indices (-1 and nodes[c] are the
// pads beyond the box); the window's outermost layers are pads (outside, edges into them cut
// half-way: the caps on the box faces), value(id) at the others (the solid: > 0).
TriMesh mesh_window(const PartLattice& lat, const std::array<int, 3>& lo,
                    const std::array<int, 3>& hi,
                    const std::function<double(std::size_t)>& value) {
  NodeLattice nl;
  for (int c = 0; c < 3; ++c) {
    nl.nodes[c] = hi[c] - lo[c] + 1;
    nl.spacing[c] = lat.spacing[c];
    nl.origin[c] = lat.origin[c] + (lo[c] + 0.5) * lat.spacing[c];
  }
  nl.pad_outside = true;
  nl.layer = [&](int k, double* v) {
    const int kk = k + lo[2];
    const int nx = nl.nodes[0], ny = nl.nodes[1];
    FirstException errors;  // value is the caller's function
#pragma omp parallel for schedule(static)
    for (int j = 0; j < ny; ++j)
      errors.run([&] {
        const int jj = j + lo[1];
        for (int i = 0; i < nx; ++i) {
          const int ii = i + lo[0];
          const bool pad = ii < 0 || jj < 0 || kk < 0 || ii >= lat.nodes[0] ||
                           jj >= lat.nodes[1] || kk >= lat.nodes[2];
          v[std::size_t(j) * nx + i] = pad ? 0.0 : value(lat.index(ii, jj, kk));
        }
      });
    errors.rethrow();
  };
  return extract_isosurface(nl, 0.0);
}

}  // namespace

PartLattice sample_part(const Field& g, const Vec3& size, double cell_size,
                        const std::function<double(double)>& transform, int refine) {
  if (!(cell_size > 0) || !std::isfinite(cell_size))
    throw std::invalid_argument(fmt::format("part: cell size {} must be > 0", cell_size));
  const int n = g.n();
  const double h = cell_size / n;
  PartLattice lat;
  for (int c = 0; c < 3; ++c) {
    if (!(size[c] > 0) || !std::isfinite(size[c]))
      throw std::invalid_argument(fmt::format("part: box size {} must be > 0", size[c]));
    const double nodes = std::ceil(size[c] / h - 1e-9) * std::max(1, refine);
    if (nodes < 2 || nodes > kMaxNodesPerAxis)
      throw std::invalid_argument(fmt::format(
          "part: the box edge {} is {} grid spacings (cell size / N = {:.4g}); accepted: 2 .. {}",
          size[c], nodes, h, kMaxNodesPerAxis));
    lat.nodes[c] = int(nodes);
    lat.spacing[c] = size[c] / nodes;
    lat.size[c] = size[c];
  }
  fill_part(lat, g, cell_size, transform);
  return lat;
}

void fill_part(PartLattice& lat, const Field& g, double cell_size,
               const std::function<double(double)>& transform) {
  const int n = g.n();
  // Per axis: the lower cell index and weight of each node's position (periodic).
  std::array<std::vector<int>, 3> cell;
  std::array<std::vector<double>, 3> weight;
  for (int c = 0; c < 3; ++c) {
    cell[c].resize(lat.nodes[c]);
    weight[c].resize(lat.nodes[c]);
    for (int m = 0; m < lat.nodes[c]; ++m) {
      const double x = (m + 0.5) * lat.spacing[c] / cell_size * n - 0.5;  // in cell indices
      double f = std::floor(x), t = x - f;
      if (t < 1e-9) t = 0.0;
      if (t > 1.0 - 1e-9) f += 1.0, t = 0.0;
      cell[c][m] = int(((long(f) % n) + n) % n);
      weight[c][m] = t;
    }
  }
  lat.a.resize(lat.count());
  FirstException errors;  // transform is the caller's function
#pragma omp parallel for schedule(static)
  for (int k = 0; k < lat.nodes[2]; ++k)
    errors.run([&] {
      for (int j = 0; j < lat.nodes[1]; ++j)
        for (int i = 0; i < lat.nodes[0]; ++i) {
          const int i0 = cell[0][i], j0 = cell[1][j], k0 = cell[2][k];
          const int i1 = (i0 + 1) % n, j1 = (j0 + 1) % n, k1 = (k0 + 1) % n;
          const double tx = weight[0][i], ty = weight[1][j], tz = weight[2][k];
          auto lerp = [](double p, double q, double t) {
            return t == 0.0 ? p : p + t * (q - p);
          };
          const double v = lerp(lerp(lerp(g(i0, j0, k0), g(i1, j0, k0), tx),
                                     lerp(g(i0, j1, k0), g(i1, j1, k0), tx), ty),
                                lerp(lerp(g(i0, j0, k1), g(i1, j0, k1), tx),
                                     lerp(g(i0, j1, k1), g(i1, j1, k1), tx), ty),
                                tz);
          lat.a[lat.index(i, j, k)] = float(transform(v));
        }
    });
  errors.rethrow();
}

PartTopology clean_part(PartLattice& lat, double level, bool keep_fragments) {
  const auto t0 = std::chrono::steady_clock::now();
  PartTopology t;
  lat.removed.assign(lat.count(), 0);
  {
    const std::vector<std::uint32_t> root =
        label_components(lat, [&](std::size_t id) { return lat.value(id, level) > 0.0; });
    const std::map<std::uint32_t, ComponentBox> boxes = component_boxes(lat, root);
    t.solid_components = boxes.size();
    std::uint32_t largest = kNoRoot;
    std::size_t most = 0;
    for (const auto& [r, b] : boxes)
      if (b.nodes > most) most = b.nodes, largest = r;
    for (const auto& [r, b] : boxes) {
      if (r == largest) continue;
      ++t.fragments;
      // The fragment's own mesh, in a window around it: its volume as the part's mesh has it.
      // Two layers beyond it (the outer one a pad) unless it touches the box there.
      const std::uint32_t me = r;
      std::array<int, 3> lo, hi;
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::max(b.lo[c] - 2, -1);
        hi[c] = std::min(b.hi[c] + 2, lat.nodes[c]);
      }
      const TriMesh m = mesh_window(lat, lo, hi, [&](std::size_t id) -> double {
        return root[id] == me || root[id] == kNoRoot ? lat.value(id, level) : double(kRemoved);
      });
      t.fragment_volumes.push_back(mesh_volume(m));
      t.fragment_volume += t.fragment_volumes.back();
    }
    std::sort(t.fragment_volumes.rbegin(), t.fragment_volumes.rend());
    if (!keep_fragments && t.fragments > 0) {
      t.fragments_removed = true;
      for (std::size_t id = 0; id < root.size(); ++id)
        if (root[id] != kNoRoot && root[id] != largest) lat.removed[id] = 1;
    }
  }
  {
    const std::vector<std::uint32_t> root = label_components(
        lat, [&](std::size_t id) { return !(lat.value(id, level) > 0.0) || lat.removed[id] != 0; });
    const std::map<std::uint32_t, ComponentBox> boxes = component_boxes(lat, root);
    t.pore_components = boxes.size();
    const double node_volume = lat.spacing[0] * lat.spacing[1] * lat.spacing[2];
    for (const auto& [r, b] : boxes) {
      for (int c = 0; c < 3; ++c)
        if ((b.faces >> (2 * c) & 3u) == 3u) t.pore_percolates[c] = true;
      if (b.faces == 0) {
        ++t.closed_pores;
        t.closed_pore_volume += double(b.nodes) * node_volume;
      }
    }
  }
  t.seconds = seconds_since(t0);
  return t;
}

TriMesh mesh_part(const PartLattice& lat, double level) {
  const bool any_removed = !lat.removed.empty();
  return mesh_window(lat, {-1, -1, -1}, lat.nodes, [&](std::size_t id) -> double {
    return any_removed && lat.removed[id] ? double(kRemoved) : lat.value(id, level);
  });
}

nlohmann::json part_topology_json(const PartTopology& t, const std::string& units) {
  return {{"solid_components", t.solid_components},
          {"fragments", t.fragments},
          {"fragments_removed", t.fragments_removed},
          {"fragment_volume", t.fragment_volume},
          {"fragment_volumes", t.fragment_volumes},
          {"volume_units", units + "^3"},
          {"pore_components", t.pore_components},
          {"pore_percolates",
           {{"x", t.pore_percolates[0]}, {"y", t.pore_percolates[1]}, {"z", t.pore_percolates[2]}}},
          {"closed_pores", t.closed_pores},
          {"closed_pore_volume", t.closed_pore_volume},
          {"method",
           "components of the nodes along the Kuhn tetrahedra's edges (exact for the "
           "piecewise-linear solid and pore space); fragment volumes from their own meshes"},
          {"seconds", t.seconds}};
}

void check_fragment_share(const PartTopology& t, double volume, double tol,
                          const std::string& units) {
  if (!t.fragments_removed || !(t.fragment_volume > tol * volume)) return;
  throw FragmentRemovalError(fmt::format(
      "the solid is in {} pieces: removing all but the largest would take {:.4g} {}^3, {:.3g} "
      "of the part's volume (more than {:g}), so nothing was written. The member is not a "
      "connected lattice (another topology, or a field of separate pieces); --keep-fragments "
      "writes every piece",
      t.solid_components, t.fragment_volume, units, t.fragment_volume / volume, tol));
}

}  // namespace cmcsurf
