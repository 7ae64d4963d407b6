#include "mesh/periodic_mesher.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "grid/kuhn.h"

#ifdef CMCSURF_HAVE_CGAL
// CGAL 5.5's structural filtering does not compile for the periodic mesher's point-removal
// traits (a point is a (point, offset) pair there); the plain locate is used instead.
#define CGAL_NO_STRUCTURAL_FILTERING
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Periodic_3_mesh_3/config.h>
#include <CGAL/Periodic_3_mesh_triangulation_3.h>
#include <CGAL/make_periodic_3_mesh_3.h>
#endif

namespace cmcsurf {

double kuhn_interpolate(const std::vector<double>& g, int n, const Vec3& p) {
  // Cell centres sit at (i + 1/2) / n.
  int i0[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    const double u = p[a] * n - 0.5;
    const double f = std::floor(u);
    t[a] = u - f;
    i0[a] = int(((long long)(f) % n + n) % n);
  }
  double v[8];
  for (int c = 0; c < 8; ++c) {
    const int i = (i0[0] + kCubeCorner[c][0]) % n, j = (i0[1] + kCubeCorner[c][1]) % n,
              k = (i0[2] + kCubeCorner[c][2]) % n;
    v[c] = g[(std::size_t(k) * n + j) * n + i];
  }
  // The Kuhn tet holding p: corner 0 -> +e_a -> +e_a + e_b -> corner 7 with t_a >= t_b >= t_c.
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int x, int y) { return t[x] > t[y]; });
  const int c1 = 1 << order[0], c2 = c1 | (1 << order[1]);
  return v[0] + t[order[0]] * (v[c1] - v[0]) + t[order[1]] * (v[c2] - v[c1]) +
         t[order[2]] * (v[7] - v[c2]);
}

#ifdef CMCSURF_HAVE_CGAL

bool periodic_mesher_available() { return true; }
std::string periodic_mesher_name() {
  return std::string("CGAL ") + CGAL_VERSION_STR + " Periodic_3_mesh_3";
}

PeriodicTets mesh_periodic_solid(const Field& g, double level, const PeriodicMeshCriteria& c) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Domain = CGAL::Labeled_mesh_domain_3<K>;
  using Tr = CGAL::Periodic_3_mesh_triangulation_3<Domain>::type;
  using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
  using Criteria = CGAL::Mesh_criteria_3<Tr>;
  namespace params = CGAL::parameters;

  const int n = g.n();
  std::vector<double> values(std::size_t(n) * n * n);
  bool inside = false;
  for_each_cell(g, [&](int i, int j, int k) {
    values[(std::size_t(k) * n + j) * n + i] = g(i, j, k);
    inside = inside || g(i, j, k) > level;
  });
  if (!inside) throw std::runtime_error("the solid is empty: nothing to mesh");
  // CGAL's domain is where the function is negative.
  auto f = [&values, n, level](const K::Point_3& p) {
    return K::FT(level - kuhn_interpolate(values, n, {p.x(), p.y(), p.z()}));
  };
  // Intersections with the surface to 1e-6 of the cell, not CGAL's default 1e-3 (which moves
  // the surface by ~1e-3 and the volume by ~0.3 %).
  Domain domain = Domain::create_implicit_mesh_domain(
      f, K::Iso_cuboid_3(0, 0, 0, 1, 1, 1), params::relative_error_bound = 1e-6);
  Criteria criteria(params::facet_angle = c.facet_angle, params::facet_size = c.facet_size,
                    params::facet_distance = c.facet_distance,
                    params::cell_radius_edge_ratio = c.radius_edge,
                    params::cell_size = c.cell_radius);
  // The perturber draws from CGAL's global generator: reseeded. CGAL's default stops the
  // perturber and the exuder after as long as the refinement took (a wall-clock limit), so runs
  // differed by a few tets; without the limit they repeat bit for bit, and the bounds stop them
  // once every tet's smallest angle is above them (unbounded, they took 4x as long).
  CGAL::get_default_random() = CGAL::Random(0);
  const double limit = c.repeatable ? 0.0 : -1.0;
  const auto perturb = params::perturb(params::time_limit = limit,
                                       params::sliver_bound = c.perturb_bound_deg);
  const auto exude =
      params::exude(params::time_limit = limit, params::sliver_bound = c.exude_bound_deg);
  C3t3 c3t3 = !c.repeatable ? CGAL::make_periodic_3_mesh_3<C3t3>(domain, criteria)
              : c.perturb   ? CGAL::make_periodic_3_mesh_3<C3t3>(domain, criteria, perturb, exude)
                            : CGAL::make_periodic_3_mesh_3<C3t3>(domain, criteria,
                                                                 params::no_perturb(), exude);
  const Tr& tr = c3t3.triangulation();

  PeriodicTets out;
  std::unordered_map<Tr::Vertex_handle, std::int32_t> id;
  for (auto cit = c3t3.cells_in_complex_begin(); cit != c3t3.cells_in_complex_end(); ++cit) {
    std::array<std::int32_t, 4> tet;
    std::array<std::array<std::int8_t, 3>, 4> off;
    std::array<Vec3, 4> corner;
    for (int i = 0; i < 4; ++i) {
      const Tr::Vertex_handle v = cit->vertex(i);
      auto [it, fresh] = id.try_emplace(v, std::int32_t(out.vertices.size()));
      if (fresh) {
        const auto p = tr.construct_point(tr.point(v), Tr::Offset(0, 0, 0));
        out.vertices.push_back({p.x(), p.y(), p.z()});
      }
      const Tr::Offset o = tr.int_to_off(cit->offset(i));
      tet[i] = it->second;
      off[i] = {std::int8_t(o.x()), std::int8_t(o.y()), std::int8_t(o.z())};
      const Vec3& q = out.vertices[std::size_t(it->second)];
      corner[i] = {q[0] + o.x(), q[1] + o.y(), q[2] + o.z()};
    }
    if (tet_volume(corner[0], corner[1], corner[2], corner[3]) < 0) {
      std::swap(tet[2], tet[3]);
      std::swap(off[2], off[3]);
    }
    out.tets.push_back(tet);
    out.offsets.push_back(off);
  }
  if (out.tets.empty()) throw std::runtime_error("the mesher returned no tetrahedra");
  return out;
}

#else

bool periodic_mesher_available() { return false; }
std::string periodic_mesher_name() { return "none (built without CGAL)"; }

PeriodicTets mesh_periodic_solid(const Field&, double, const PeriodicMeshCriteria&) {
  throw std::runtime_error(
      "volume meshes need CGAL (Debian libcgal-dev, libgmp-dev, libmpfr-dev), which was not "
      "found when cmcsurf was configured; install it and reconfigure (scripts/setup.sh)");
}

#endif

}  // namespace cmcsurf
