// Indexed triangle meshes and their checks: area, enclosed volume, edges, Euler characteristic.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace cmcsurf {

using Vec3 = std::array<double, 3>;

// Counter-clockwise triangles seen from outside (the normal (b - a) x (c - a) points out).
struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  // > 0 on an axis where the mesh lives on a torus of that period (the untiled periodic
  // surface): edge vectors are taken by the minimum-image rule. 0: an ordinary mesh.
  Vec3 period{0.0, 0.0, 0.0};
};

struct MeshStats {
  std::size_t vertices = 0, edges = 0, triangles = 0;
  std::size_t boundary_edges = 0;      // used by one triangle
  std::size_t nonmanifold_edges = 0;   // used by more than two triangles
  std::size_t misoriented_edges = 0;   // used twice in the same direction
  std::size_t nonmanifold_vertices = 0;  // triangle fan not a single disk or half-disk
  std::size_t degenerate_triangles = 0;  // repeated index or zero area
  std::size_t duplicate_triangles = 0;   // same vertex set as another triangle
  std::size_t unused_vertices = 0;
  long euler = 0;                        // V - E + F
  double area = 0.0;
  double volume = 0.0;                   // divergence theorem; meaningful when closed
  Vec3 min{0, 0, 0}, max{0, 0, 0};       // bounding box
  bool closed() const { return boundary_edges == 0; }
  bool manifold() const {
    return nonmanifold_edges == 0 && nonmanifold_vertices == 0 && misoriented_edges == 0;
  }
};

// Edge vector b - a (minimum image on periodic axes).
Vec3 mesh_edge(const TriMesh& m, std::uint32_t a, std::uint32_t b);

double mesh_area(const TriMesh& m);

double dot(const Vec3& a, const Vec3& b);
Vec3 sub(const Vec3& a, const Vec3& b);
Vec3 cross(const Vec3& a, const Vec3& b);
double norm(const Vec3& a);  // Euclidean length
// Squared distance from p to the triangle (a, b, c).
double point_triangle_distance2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
// Signed volume enclosed by a closed, outward-oriented, non-periodic mesh.
double mesh_volume(const TriMesh& m);

MeshStats analyze_mesh(const TriMesh& m);
// Only min and max set (analyze_mesh also counts edges, seconds on a large part).
MeshStats bounding_box(const TriMesh& m);

}  // namespace cmcsurf
