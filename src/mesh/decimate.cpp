#include "mesh/decimate.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
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

Decimated decimate_solid(const TriMesh& m, const DecimateParams& p) {
  if (p.max_triangles == 0 && !(p.tolerance > 0))
    throw std::invalid_argument("decimate: give a triangle budget or a tolerance");
  const auto t0 = std::chrono::steady_clock::now();
  Decimated d;
  d.triangles_before = m.triangles.size();
  std::vector<float> xyz(3 * m.vertices.size());
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    for (int c = 0; c < 3; ++c) xyz[3 * v + c] = float(m.vertices[v][c]);
  // The flat caps on the bounding box's faces are kept as they are: collapses within a plane
  // of collinear lattice points leave zero-area and folded triangles. Their rim becomes the
  // border of the rest, which meshopt_SimplifyLockBorder keeps, so caps and walls still meet.
  const MeshStats box = analyze_mesh(m);
  const double eps = 1e-9 * std::max({box.max[0] - box.min[0], box.max[1] - box.min[1], box.max[2] - box.min[2]});
  auto on_face = [&](const std::array<std::uint32_t, 3>& t) {
    for (int c = 0; c < 3; ++c)
      for (double plane : {box.min[c], box.max[c]}) {
        bool all = true;
        for (std::uint32_t v : t) all = all && std::abs(m.vertices[v][c] - plane) <= eps;
        if (all) return true;
      }
    return false;
  };
  std::vector<unsigned> indices, caps;
  for (const auto& t : m.triangles) (on_face(t) ? caps : indices).insert((on_face(t) ? caps : indices).end(), t.begin(), t.end());
  std::vector<unsigned> out(indices.size());
  const std::size_t cap_triangles = caps.size() / 3;
  const float scale = meshopt_simplifyScale(xyz.data(), m.vertices.size(), 3 * sizeof(float));
  const double volume = mesh_volume(m);
  const std::size_t shells = mesh_shell_count(m);
  std::size_t target =
      p.max_triangles > cap_triangles ? p.max_triangles - cap_triangles : (p.max_triangles > 0 ? 1 : 0);
  double error = p.tolerance > 0 ? p.tolerance : 1e30;
  d.mesh = m;
  d.triangles_after = m.triangles.size();
  for (d.attempts = 1; d.attempts <= kMaxAttempts; ++d.attempts) {
    float achieved = 0.0f;
    const std::size_t count = meshopt_simplify(
        out.data(), indices.data(), indices.size(), xyz.data(), m.vertices.size(),
        3 * sizeof(float), std::min(3 * target, indices.size()), float(std::min(error / scale, 1e30)),
        meshopt_SimplifyLockBorder, &achieved);
    if (count >= indices.size()) {  // nothing left to remove within the checks
      d.attempts = kMaxAttempts + 1;
      break;
    }
    out.resize(count);
    out.insert(out.end(), caps.begin(), caps.end());
    // A compact mesh of the vertices still used, in the input's double coordinates.
    TriMesh r;
    std::vector<std::uint32_t> remap(m.vertices.size(), UINT32_MAX);
    r.triangles.resize(out.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i) {
      std::uint32_t& slot = remap[out[i]];
      if (slot == UINT32_MAX) {
        slot = std::uint32_t(r.vertices.size());
        r.vertices.push_back(m.vertices[out[i]]);
      }
      r.triangles[i / 3][i % 3] = slot;
    }
    const MeshStats s = analyze_mesh(r);
    const double change = std::abs(s.volume - volume) / std::abs(volume);
    const bool ok = s.closed() && s.manifold() && s.degenerate_triangles == 0 &&
                    s.duplicate_triangles == 0 && mesh_shell_count(r) == shells &&
                    change <= p.max_volume_change;
    if (ok) {
      d.mesh = std::move(r);
      d.triangles_after = d.mesh.triangles.size();
      d.error = double(achieved) * scale;
      d.volume_change = change;
      break;
    }
    // Too far: a larger budget, a smaller error.
    out.resize(indices.size());
    if (target > 0) target = target + target / 2;
    if (p.tolerance > 0) error *= 0.5;
  }
  d.applied = d.attempts <= kMaxAttempts;
  if (!d.applied) d.attempts = kMaxAttempts;
  d.within_budget = p.max_triangles == 0 || d.triangles_after <= p.max_triangles;
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return d;
}

nlohmann::json decimated_json(const Decimated& d, const DecimateParams& p,
                              const std::string& units) {
  return {{"method", "meshoptimizer 0.18 meshopt_simplify (quadric edge collapses), accepted when "
                     "closed, manifold, as many shells and the volume within max_volume_change"},
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
