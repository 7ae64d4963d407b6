#include "mesh/shape.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/MeshToVolume.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>

#include "common/input_file.h"
#include "mesh/union_find.h"
#include "parallel/first_exception.h"

namespace cmcsurf {

TriMesh read_stl(const std::filesystem::path& path) {
  require_regular_file(path, "STL file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot open '{}'", path.string()));
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::vector<Vec3> corners;
  std::uint32_t count = 0;
  if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);
  if (bytes.size() >= 84 && bytes.size() == 84 + 50 * std::size_t(count)) {  // binary
    for (std::uint32_t t = 0; t < count; ++t)
      for (int v = 0; v < 3; ++v) {
        float xyz[3];
        std::memcpy(xyz, bytes.data() + 84 + 50 * std::size_t(t) + 12 + 12 * v, 12);
        corners.push_back({xyz[0], xyz[1], xyz[2]});
      }
  } else {  // ASCII: every "vertex x y z"
    std::istringstream text(bytes);
    for (std::string word; text >> word;)
      if (word == "vertex") {
        Vec3 p;
        if (!(text >> p[0] >> p[1] >> p[2]))
          throw std::runtime_error(
              fmt::format("'{}': a vertex without three numbers", path.string()));
        corners.push_back(p);
      }
  }
  if (corners.empty() || corners.size() % 3 != 0)
    throw std::runtime_error(fmt::format("'{}' is not an STL file with triangles", path.string()));
  TriMesh m;
  std::map<Vec3, std::uint32_t> index;
  for (std::size_t c = 0; c < corners.size(); c += 3) {
    std::array<std::uint32_t, 3> t;
    for (int v = 0; v < 3; ++v) {
      const auto [it, added] = index.emplace(corners[c + v], std::uint32_t(m.vertices.size()));
      if (added) m.vertices.push_back(corners[c + v]);
      t[v] = it->second;
    }
    m.triangles.push_back(t);
  }
  return m;
}

bool shells_may_overlap(const TriMesh& shape) {
  // Shells: components of the vertices joined by the triangles' edges (union-find).
  std::vector<std::uint32_t> parent(shape.vertices.size());
  for (std::uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
  const auto root = [&](std::uint32_t v) { return find_root(parent, v); };
  for (const auto& t : shape.triangles)
    for (int e = 0; e < 2; ++e) parent[root(t[e])] = root(t[e + 1]);
  std::map<std::uint32_t, std::pair<Vec3, Vec3>> boxes;  // per shell: min, max
  for (std::uint32_t v = 0; v < parent.size(); ++v) {
    const Vec3& p = shape.vertices[v];
    const auto [it, added] = boxes.emplace(root(v), std::pair{p, p});
    for (int c = 0; c < 3; ++c) {
      it->second.first[c] = std::min(it->second.first[c], p[c]);
      it->second.second[c] = std::max(it->second.second[c], p[c]);
    }
  }
  for (auto a = boxes.begin(); a != boxes.end(); ++a)
    for (auto b = std::next(a); b != boxes.end(); ++b) {
      bool overlap = true;
      for (int c = 0; c < 3; ++c)
        overlap = overlap && a->second.first[c] < b->second.second[c] &&
                  b->second.first[c] < a->second.second[c];
      if (overlap) return true;
    }
  return false;
}

std::vector<float> shape_distance(const TriMesh& shape, const PartLattice& lat, double band) {
  openvdb::initialize();
  // One voxel of the lattice's smallest spacing; the band in voxels.
  const double voxel = std::min({lat.spacing[0], lat.spacing[1], lat.spacing[2]});
  auto transform = openvdb::math::Transform::createLinearTransform(voxel);
  std::vector<openvdb::Vec3s> points;
  points.reserve(shape.vertices.size());
  for (const Vec3& v : shape.vertices) points.emplace_back(float(v[0]), float(v[1]), float(v[2]));
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(shape.triangles.size());
  for (const auto& t : shape.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  const float half_width = float(std::max(3.0, band / voxel + 2.0));
  const openvdb::FloatGrid::Ptr raw =
      openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, half_width);
  // The union of the shells: faces of one shell inside another leave a band of small negative
  // distances, which a rebuild (re-extracting the zero crossings) drops. It rounds edges by
  // a fraction of a voxel, so only shells that may overlap are rebuilt.
  const openvdb::FloatGrid::Ptr grid =
      shells_may_overlap(shape) ? openvdb::tools::levelSetRebuild(*raw, 0.0f, half_width) : raw;
  std::vector<float> d(lat.count());
  FirstException errors;  // a sampler's accessor allocates
#pragma omp parallel for schedule(static)
  for (int k = 0; k < lat.nodes[2]; ++k)
    errors.run([&] {
      openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(*grid);
      for (int j = 0; j < lat.nodes[1]; ++j)
        for (int i = 0; i < lat.nodes[0]; ++i) {
          const openvdb::Vec3R p(lat.origin[0] + (i + 0.5) * lat.spacing[0],
                                 lat.origin[1] + (j + 0.5) * lat.spacing[1],
                                 lat.origin[2] + (k + 0.5) * lat.spacing[2]);
          d[lat.index(i, j, k)] = float(std::clamp(double(sampler.wsSample(p)), -band, band));
        }
    });
  errors.rethrow();
  return d;
}

}  // namespace cmcsurf
