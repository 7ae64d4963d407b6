#include "mesh/decimate.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModHausdorffT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <chrono>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace cmcsurf {

namespace {

constexpr int kMaxAttempts = 8;

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

std::size_t mesh_shell_count(const TriMesh& m) {
  std::vector<std::uint32_t> parent(m.vertices.size());
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<std::uint8_t> used(m.vertices.size(), 0);
  for (const auto& t : m.triangles)
    for (int c = 0; c < 3; ++c) {
      used[t[c]] = 1;
      const std::uint32_t a = find_root(parent, t[0]), b = find_root(parent, t[c]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::size_t shells = 0;
  for (std::size_t v = 0; v < parent.size(); ++v) shells += used[v] && find_root(parent, std::uint32_t(v)) == v;
  return shells;
}

namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// Largest distance from the points to the mesh (one-sided), by a uniform grid of triangle
// bounding boxes searched in growing shells around each point.
double max_distance_to(const TriMesh& m, const std::vector<Vec3>& points) {
  const MeshStats st = analyze_mesh(m);
  double mean_edge = 0.0;
  for (const auto& t : m.triangles) mean_edge += std::sqrt(dot(sub(m.vertices[t[1]], m.vertices[t[0]]), sub(m.vertices[t[1]], m.vertices[t[0]])));
  mean_edge = std::max(mean_edge / std::max<std::size_t>(1, m.triangles.size()), 1e-12);
  const double cell = 2.0 * mean_edge;
  std::array<int, 3> dims;
  for (int c = 0; c < 3; ++c) dims[c] = std::max(1, int(std::ceil((st.max[c] - st.min[c]) / cell)) + 1);
  auto bin = [&](const Vec3& p, int c) { return std::clamp(int((p[c] - st.min[c]) / cell), 0, dims[c] - 1); };
  std::vector<std::vector<std::uint32_t>> bins(std::size_t(dims[0]) * dims[1] * dims[2]);
  auto id = [&](int i, int j, int k) { return (std::size_t(k) * dims[1] + j) * dims[0] + i; };
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    std::array<int, 3> lo{dims[0], dims[1], dims[2]}, hi{-1, -1, -1};
    for (std::uint32_t v : m.triangles[t])
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], bin(m.vertices[v], c)), hi[c] = std::max(hi[c], bin(m.vertices[v], c));
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) bins[id(i, j, k)].push_back(std::uint32_t(t));
  }
  double worst = 0.0;
#pragma omp parallel for reduction(max : worst) schedule(dynamic, 1024)
  for (std::size_t q = 0; q < points.size(); ++q) {
    const Vec3& p = points[q];
    const int b[3] = {bin(p, 0), bin(p, 1), bin(p, 2)};
    double best = std::numeric_limits<double>::infinity();
    const int max_ring = std::max({dims[0], dims[1], dims[2]});
    for (int ring = 0; ring <= max_ring; ++ring) {
      // Nothing beyond this ring can be closer than (ring - 1) cells.
      if (ring > 0 && (ring - 1) * cell > std::sqrt(best)) break;
      for (int k = b[2] - ring; k <= b[2] + ring; ++k)
        for (int j = b[1] - ring; j <= b[1] + ring; ++j)
          for (int i = b[0] - ring; i <= b[0] + ring; ++i) {
            if (std::max({std::abs(i - b[0]), std::abs(j - b[1]), std::abs(k - b[2])}) != ring) continue;
            if (i < 0 || j < 0 || k < 0 || i >= dims[0] || j >= dims[1] || k >= dims[2]) continue;
            for (std::uint32_t t : bins[id(i, j, k)]) {
              const auto& v = m.triangles[t];
              best = std::min(best, point_triangle_distance2(p, m.vertices[v[0]], m.vertices[v[1]], m.vertices[v[2]]));
            }
          }
    }
    worst = std::max(worst, best);
  }
  return std::sqrt(worst);
}

}  // namespace

Decimated decimate_solid(const TriMesh& m, const DecimateParams& p) {
  if (p.max_triangles == 0 && !(p.tolerance > 0))
    throw std::invalid_argument("decimate: give a triangle budget or a tolerance");
  const auto t0 = std::chrono::steady_clock::now();
  Decimated d;
  d.triangles_before = m.triangles.size();
  d.mesh = m;
  d.triangles_after = m.triangles.size();
  const MeshStats box = analyze_mesh(m);
  const double extent = std::max({box.max[0] - box.min[0], box.max[1] - box.min[1], box.max[2] - box.min[2]});
  const double eps = 1e-9 * extent;
  const double volume = box.volume;
  const std::size_t shells = mesh_shell_count(m);
  // Vertices on the box's edges (on two of its face planes) stay where they are: collapses
  // along such a line of collinear points leave zero-area triangles.
  auto on_box_edge = [&](const Vec3& v) {
    int planes = 0;
    for (int c = 0; c < 3; ++c)
      planes += std::abs(v[c] - box.min[c]) <= eps || std::abs(v[c] - box.max[c]) <= eps;
    return planes >= 2;
  };
  double tolerance = p.tolerance;
  std::size_t target = p.max_triangles;
  for (d.attempts = 1; d.attempts <= kMaxAttempts; ++d.attempts) {
    OMesh om;
    std::vector<OMesh::VertexHandle> vh(m.vertices.size());
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
      vh[v] = om.add_vertex(OMesh::Point(m.vertices[v][0], m.vertices[v][1], m.vertices[v][2]));
      if (on_box_edge(m.vertices[v])) om.status(vh[v]).set_locked(true);
    }
    for (const auto& t : m.triangles) om.add_face(vh[t[0]], vh[t[1]], vh[t[2]]);
    om.update_face_normals();
    OpenMesh::Decimater::DecimaterT<OMesh> decimater(om);
    OpenMesh::Decimater::ModQuadricT<OMesh>::Handle quadric;
    decimater.add(quadric);
    decimater.module(quadric).unset_max_err();
    OpenMesh::Decimater::ModNormalFlippingT<OMesh>::Handle flipping;
    decimater.add(flipping);
    decimater.module(flipping).set_max_normal_deviation(60.0);
    // No collapse may leave a triangle more needle-like than this unless it improves on the
    // one it replaces (marching tetrahedra's slivers may go, zero-area triangles not come).
    OpenMesh::Decimater::ModAspectRatioT<OMesh>::Handle aspect;
    decimater.add(aspect);
    decimater.module(aspect).set_aspect_ratio(20.0f);
    decimater.module(aspect).set_binary(true);
    OpenMesh::Decimater::ModHausdorffT<OMesh>::Handle hausdorff;
    if (tolerance > 0) {
      decimater.add(hausdorff);
      decimater.module(hausdorff).set_tolerance(tolerance);
    }
    decimater.initialize();
    if (target > 0) decimater.decimate_to_faces(0, target);
    else decimater.decimate(0);
    om.garbage_collection();
    TriMesh r;
    r.vertices.reserve(om.n_vertices());
    for (const auto& v : om.vertices()) {
      const OMesh::Point& q = om.point(v);
      r.vertices.push_back({q[0], q[1], q[2]});
    }
    for (const auto& f : om.faces()) {
      std::array<std::uint32_t, 3> t{};
      int c = 0;
      for (const auto& v : om.fv_range(f)) t[c++] = std::uint32_t(v.idx());
      r.triangles.push_back(t);
    }
    const MeshStats s = analyze_mesh(r);
    const double change = std::abs(s.volume - volume) / std::abs(volume);
    bool ok = s.closed() && s.manifold() && s.degenerate_triangles == 0 &&
              s.duplicate_triangles == 0 && mesh_shell_count(r) == shells &&
              change <= p.max_volume_change && r.triangles.size() < m.triangles.size();
    const double error = ok ? max_distance_to(r, m.vertices) : 0.0;
    if (p.tolerance > 0 && error > p.tolerance) ok = false;
    if (ok) {
      d.error = error;
      d.mesh = std::move(r);
      d.triangles_after = d.mesh.triangles.size();
      d.volume_change = change;
      break;
    }
    // Too far: a larger budget, a smaller error.
    if (target > 0) target += target / 2;
    if (tolerance > 0) tolerance *= 0.5;
  }
  d.applied = d.attempts <= kMaxAttempts;
  if (!d.applied) d.attempts = kMaxAttempts;
  d.within_budget = p.max_triangles == 0 || d.triangles_after <= p.max_triangles;
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return d;
}

nlohmann::json decimated_json(const Decimated& d, const DecimateParams& p,
                              const std::string& units) {
  return {{"method", "OpenMesh 9 decimater: quadric edge collapses that keep the mesh manifold "
                     "(link condition), no normal flips over 60 degrees, no new triangle with an "
                     "aspect ratio over 20 unless it improves, within the Hausdorff tolerance "
                     "when given, the box's edges fixed; accepted when closed, manifold, as many "
                     "shells and the volume within max_volume_change"},
          {"error_note", "largest distance from the input's vertices to the decimated mesh"},
          {"max_triangles", p.max_triangles},
          {"tolerance", p.tolerance},
          {"max_volume_change", p.max_volume_change},
          {"applied", d.applied},
          {"triangles_before", d.triangles_before},
          {"triangles_after", d.triangles_after},
          {"within_budget", d.within_budget},
          {"error", d.error},
          {"error_units", units},
          {"volume_change", d.volume_change},
          {"attempts", d.attempts},
          {"seconds", d.seconds}};
}

}  // namespace cmcsurf
