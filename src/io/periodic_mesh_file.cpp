#include "io/periodic_mesh_file.h"

#include "common/atomic_file.h"

namespace cmcsurf {

nlohmann::json periodic_mesh_stats_json(const PeriodicSurfaceMesh& m) {
  const MeshStats s = analyze_mesh(m.tri_mesh());
  return {{"vertices", s.vertices},
          {"edges", s.edges},
          {"triangles", s.triangles},
          {"euler_characteristic", s.euler},
          {"area", s.area},
          {"closed", s.closed()},
          {"manifold", s.manifold()}};
}

void write_periodic_mesh_json(const std::filesystem::path& path, const PeriodicSurfaceMesh& m,
                              const nlohmann::json& extra) {
  nlohmann::json j = {
      {"format", "cmcsurf periodic surface mesh 1"},
      {"cell", "the computed unit cell [0, 1)^3 (edge a = 1); the surface phi = 1/2"},
      {"offsets_note",
       "triangle t is (vertices[a] + offsets[t][0], vertices[b] + offsets[t][1], vertices[c] + "
       "offsets[t][2]) for triangles[t] = (a, b, c), offsets in whole cells, offsets[t][0] = 0"},
      {"curvature_note",
       "normals point into phase 2 (phi < 1/2); mean_curvature H > 0 where phase 1 is convex; "
       "H and K of the level sets of atanh(2 phi - 1) from central differences, interpolated "
       "trilinearly to each vertex"},
      {"vertices", m.vertices},
      {"triangles", m.triangles},
      {"offsets", m.offsets},
      {"normals", m.normals},
      {"mean_curvature", m.mean_curvature},
      {"gaussian_curvature", m.gaussian_curvature},
      {"stats", periodic_mesh_stats_json(m)}};
  if (extra.is_object()) j.update(extra);
  write_file_atomic(path, j.dump() + "\n");
}

}  // namespace cmcsurf
