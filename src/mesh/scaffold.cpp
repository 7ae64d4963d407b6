#include "mesh/scaffold.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <limits>
#include <stdexcept>
#include <vector>

#include "common/wall_clock.h"
#include "measure/measures.h"
#include "measure/sharp_volume.h"
#include "mesh/marching_tets.h"
#include "mesh/part.h"
#include "parallel/first_exception.h"

namespace cmcsurf {

namespace {

// Fragments the box cuts off whole tiles hold ~1e-4 of it; more is a solid in pieces.
constexpr double kFragmentShareTol = 1e-3;

int wrap(int i, int n) { return ((i % n) + n) % n; }

}  // namespace

namespace {

// The planes of a whole field, through one buffer.
PlaneFn field_planes(const Field& phi) {
  auto buffer = std::make_shared<std::vector<double>>(std::size_t(phi.n()) * phi.n());
  return [&phi, buffer](int k) {
    const int n = phi.n();
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) (*buffer)[std::size_t(j) * n + i] = phi(i, j, k);
    return static_cast<const double*>(buffer->data());
  };
}

}  // namespace

SolidKind parse_solid_kind(const std::string& name) {
  if (name == "surface") return SolidKind::kSurface;
  if (name == "network") return SolidKind::kNetwork;
  if (name == "sheet") return SolidKind::kSheet;
  throw std::invalid_argument(fmt::format("got '{}'; accepted: surface|network|sheet", name));
}
const char* solid_kind_name(SolidKind k) {
  switch (k) {
    case SolidKind::kSurface: return "surface";
    case SolidKind::kNetwork: return "network";
    case SolidKind::kSheet: return "sheet";
  }
  return "";
}

TriMesh mesh_tiled(const TiledSampler& f, int n, const std::array<int, 3>& tiles,
                   double cell_size, double iso, bool solid) {
  const double h = cell_size / n;
  NodeLattice lat;
  // Surface: node m = cell m mod n. Solid: node m = cell m - 1, nodes 0 and last are pads.
  const int extra = solid ? 2 : 1, shift = solid ? -1 : 0;
  for (int c = 0; c < 3; ++c) {
    lat.nodes[c] = tiles[c] * n + extra;
    lat.origin[c] = (shift + 0.5) * h;
    lat.spacing[c] = h;
  }
  const int cells_x = tiles[0] * n, cells_y = tiles[1] * n, cells_z = tiles[2] * n;
  lat.pad_outside = solid;
  lat.layer = [&](int k, double* v) {
    const int nx = lat.nodes[0], ny = lat.nodes[1];
    const int ck = std::clamp(k + shift, 0, cells_z - 1) % cells_z;
    FirstException errors;  // f is the caller's function
#pragma omp parallel for schedule(static)
    for (int j = 0; j < ny; ++j)
      errors.run([&] {
        const int cj = std::clamp(j + shift, 0, cells_y - 1) % cells_y;
        for (int i = 0; i < nx; ++i) {
          const int ci = solid ? std::clamp(i + shift, 0, cells_x - 1) : i % cells_x;
          v[std::size_t(j) * nx + i] = f(ci, solid ? cj : j % cells_y, solid ? ck : k % cells_z);
        }
      });
    errors.rethrow();
  };
  return extract_isosurface(lat, iso);
}

TriMesh periodic_surface_mesh(const PlaneFn& plane, int n, double iso) {
  NodeLattice lat;
  lat.nodes = {n, n, n};
  lat.periodic = true;
  lat.origin = {0.5 / n, 0.5 / n, 0.5 / n};
  lat.spacing = {1.0 / n, 1.0 / n, 1.0 / n};
  lat.layer = [&](int k, double* v) {
    const double* p = plane(k);
    std::copy(p, p + std::size_t(n) * n, v);
  };
  return extract_isosurface(lat, iso);
}

TriMesh periodic_surface_mesh(const Field& phi, double iso) {
  return periodic_surface_mesh(field_planes(phi), phi.n(), iso);
}

Field signed_distance(const Field& phi, double band, double iso) {
  const int n = phi.n();
  const double h = 1.0 / n;
  const TriMesh surf = periodic_surface_mesh(phi, iso);
  const std::size_t cells = std::size_t(n) * n * n;
  std::vector<double> d2(cells, std::numeric_limits<double>::infinity());
  std::vector<std::int32_t> tri(cells, -1);
  auto id = [n](int i, int j, int k) { return (std::size_t(k) * n + j) * n + i; };
  auto centre = [h](int i, int j, int k) {
    return Vec3{(i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h};
  };
  // Distance from cell centre p to triangle t, with t moved by whole periods next to p.
  auto distance2 = [&](const Vec3& p, std::int32_t t) {
    const auto& v = surf.triangles[std::size_t(t)];
    Vec3 a = surf.vertices[v[0]];
    for (int c = 0; c < 3; ++c) a[c] -= std::nearbyint(a[c] - p[c]);
    const Vec3 e1 = mesh_edge(surf, v[0], v[1]), e2 = mesh_edge(surf, v[0], v[2]);
    const Vec3 b{a[0] + e1[0], a[1] + e1[1], a[2] + e1[2]};
    const Vec3 c{a[0] + e2[0], a[1] + e2[1], a[2] + e2[2]};
    return point_triangle_distance2(p, a, b, c);
  };
  // Seed: the cell centres within kSeedCells of the cube each triangle lies in get exact
  // distances; propagation alone can miss the closest triangle by a few % of h.
  constexpr int kSeedCells = 2;
  for (std::size_t t = 0; t < surf.triangles.size(); ++t) {
    const auto& v = surf.triangles[t];
    const Vec3 e1 = mesh_edge(surf, v[0], v[1]), e2 = mesh_edge(surf, v[0], v[2]);
    int cube[3];
    for (int c = 0; c < 3; ++c) {
      const double x = surf.vertices[v[0]][c] + (e1[c] + e2[c]) / 3.0;
      cube[c] = int(std::floor(x / h - 0.5));
    }
    for (int dk = -kSeedCells; dk <= 1 + kSeedCells; ++dk)
      for (int dj = -kSeedCells; dj <= 1 + kSeedCells; ++dj)
        for (int di = -kSeedCells; di <= 1 + kSeedCells; ++di) {
          const int i = wrap(cube[0] + di, n), j = wrap(cube[1] + dj, n), k = wrap(cube[2] + dk, n);
          const double dd = distance2(centre(i, j, k), std::int32_t(t));
          if (dd < d2[id(i, j, k)]) d2[id(i, j, k)] = dd, tri[id(i, j, k)] = std::int32_t(t);
        }
  }
  // Propagate closest triangles: forward sweeps take the 13 earlier neighbours, backward
  // sweeps the 13 later ones; repeat until nothing changes.
  const double band2 = band * band;
  for (int pass = 0; pass < 16; ++pass) {
    bool changed = false;
    for (int dir : {+1, -1}) {
      const int start = dir > 0 ? 0 : n - 1, stop = dir > 0 ? n : -1;
      for (int k = start; k != stop; k += dir)
        for (int j = start; j != stop; j += dir)
          for (int i = start; i != stop; i += dir) {
            const std::size_t me = id(i, j, k);
            const Vec3 p = centre(i, j, k);
            for (int dk = -1; dk <= 0; ++dk)
              for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                  if (dk == 0 && (dj > 0 || (dj == 0 && di >= 0))) continue;
                  const std::size_t nb =
                      id(wrap(i + dir * di, n), wrap(j + dir * dj, n), wrap(k + dir * dk, n));
                  const std::int32_t t = tri[nb];
                  if (t < 0 || t == tri[me] || d2[nb] > band2) continue;
                  const double dd = distance2(p, t);
                  if (dd < d2[me]) d2[me] = dd, tri[me] = t, changed = true;
                }
          }
    }
    if (!changed) break;
  }
  Field d(n, std::max(1, phi.ghost()));
  for_each_cell(n, [&](int i, int j, int k) {
    const double dist = std::min(std::sqrt(d2[id(i, j, k)]), band);
    d(i, j, k) = phi(i, j, k) > iso ? dist : -dist;
  });
  d.exchange_halo();
  return d;
}

nlohmann::json mesh_stats_json(const MeshStats& s, const std::array<int, 3>& tiles,
                               const std::string& units, bool solid) {
  const int cells = tiles[0] * tiles[1] * tiles[2];
  nlohmann::json j = {
      {"triangles", s.triangles},
      {"vertices", s.vertices},
      {"edges", s.edges},
      {"area", s.area},
      {"area_units", units + "^2"},
      // V - E + F of the file's mesh: an Euler characteristic only where the mesh is closed (a
      // solid); a surface mesh is cut open at the cell faces and tile faces.
      {"v_minus_e_plus_f", s.euler},
      {"v_minus_e_plus_f_per_cell", double(s.euler) / cells},
      {"bounding_box", {{"min", s.min}, {"max", s.max}, {"units", units}}},
      {"checks",
       {{"closed", s.closed()},
        {"manifold", s.manifold()},
        {"boundary_edges", s.boundary_edges},
        {"nonmanifold_edges", s.nonmanifold_edges},
        {"misoriented_edges", s.misoriented_edges},
        {"nonmanifold_vertices", s.nonmanifold_vertices},
        {"degenerate_triangles", s.degenerate_triangles},
        {"duplicate_triangles", s.duplicate_triangles},
        {"unused_vertices", s.unused_vertices}}}};
  if (s.closed()) j["euler_characteristic"] = s.euler;
  if (solid) {
    j["volume"] = s.volume;
    j["volume_units"] = units + "^3";
  }
  return j;
}

nlohmann::json periodic_surface_json(const Field& phi) {
  return periodic_surface_json(field_planes(phi), phi.n());
}

nlohmann::json periodic_surface_json(const PlaneFn& plane, int n) {
  const MeshStats s = analyze_mesh(periodic_surface_mesh(plane, n));
  return {{"note", "phi = 1/2 surface of one unit cell on the 3-torus, unit-cell units"},
          {"euler_characteristic", s.euler},
          {"genus", 1.0 - 0.5 * double(s.euler)},
          {"area", s.area},
          {"triangles", s.triangles},
          {"closed", s.closed()},
          {"manifold", s.manifold()}};
}

namespace {

// The report keys every kind of part has besides its mesh statistics.
void add_part_keys(nlohmann::json& r, const ScaffoldParams& p, int n,
                   const nlohmann::json& periodic, double mesh_seconds) {
  r["solid"] = solid_kind_name(p.solid);
  r["phase"] = p.other_phase ? "phi < 1/2" : "phi > 1/2";
  r["tiles"] = p.tiles;
  r["cell_size"] = p.cell_size;
  r["units"] = p.units;
  r["grid"] = n;
  r["periodic_surface"] = periodic;
  r["mesh_seconds"] = mesh_seconds;
}

void check_scaffold_params(const ScaffoldParams& p) {
  for (int c = 0; c < 3; ++c)
    if (p.tiles[c] < 1) throw std::invalid_argument("tiles must be >= 1 on every axis");
  if (!(p.cell_size > 0)) throw std::invalid_argument("cell size must be > 0");
}

}  // namespace

Scaffold build_surface_scaffold(const PlaneFn& plane, int n, const ScaffoldParams& p) {
  if (p.solid != SolidKind::kSurface)
    throw std::invalid_argument("build_surface_scaffold: a surface only");
  check_scaffold_params(p);
  const auto t0 = std::chrono::steady_clock::now();
  const double sign = p.other_phase ? -1.0 : 1.0;
  // mesh_tiled's surface lattice (node m = cell m mod n per axis), one plane per layer.
  const double h = p.cell_size / n;
  NodeLattice lat;
  for (int c = 0; c < 3; ++c) {
    lat.nodes[c] = p.tiles[c] * n + 1;
    lat.origin[c] = 0.5 * h;
    lat.spacing[c] = h;
  }
  lat.layer = [&](int k, double* v) {
    const double* values = plane(k % n);
    const int nx = lat.nodes[0], ny = lat.nodes[1];
#pragma omp parallel for schedule(static)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        v[std::size_t(j) * nx + i] = 0.5 + sign * (values[std::size_t(j % n) * n + i % n] - 0.5);
  };
  Scaffold out;
  out.mesh = extract_isosurface(lat, 0.5);
  const double mesh_seconds =
      seconds_since(t0);
  const MeshStats s = analyze_mesh(out.mesh);
  nlohmann::json& r = out.report;
  r = mesh_stats_json(s, p.tiles, p.units, false);
  const int cells = p.tiles[0] * p.tiles[1] * p.tiles[2];
  add_part_keys(r, p, n, periodic_surface_json(plane, n), mesh_seconds);
  r["area_per_cell"] = s.area / cells / (p.cell_size * p.cell_size);
  r["area_per_cell_units"] = "unit cell edge^2";
  return out;
}

Scaffold build_scaffold(const Field& phi, const ScaffoldParams& p) {
  if (p.solid == SolidKind::kSurface) return build_surface_scaffold(field_planes(phi), phi.n(), p);
  const auto t0 = std::chrono::steady_clock::now();
  const int n = phi.n();
  check_scaffold_params(p);
  const double sign = p.other_phase ? -1.0 : 1.0;
  const bool solid = p.solid != SolidKind::kSurface;
  nlohmann::json extra;
  Scaffold out;
  Field dist;
  PartTopology topology;
  if (solid) {
    // The tiles as a box of whole cells: the lattice holds the cell values themselves.
    const Vec3 size{p.tiles[0] * p.cell_size, p.tiles[1] * p.cell_size, p.tiles[2] * p.cell_size};
    PartLattice lat;
    double level = 0.0;
    if (p.solid == SolidKind::kSheet) {
      const double half = 0.5 * p.thickness / p.cell_size;  // unit-cell units
      if (!(half > 0 && half <= 0.25))
        throw std::invalid_argument("sheet thickness must be in (0, cell size / 2]");
      dist = signed_distance(phi, half + 3.0 / n);
      lat = sample_part(dist, size, p.cell_size, [](double d) { return -std::abs(d); });
      level = -half;
    } else {
      lat = sample_part(phi, size, p.cell_size, [sign](double v) { return sign * (v - 0.5); });
    }
    topology = clean_part(lat, level, p.keep_fragments);
    check_fragment_share(topology, lat.box_volume(), kFragmentShareTol, p.units);
    out.mesh = mesh_part(lat, level);
  } else {
    out.mesh = mesh_tiled(
        [&](int i, int j, int k) { return 0.5 + sign * (phi(i % n, j % n, k % n) - 0.5); }, n,
        p.tiles, p.cell_size, 0.5, false);
  }
  const double mesh_seconds =
      seconds_since(t0);
  const MeshStats s = analyze_mesh(out.mesh);
  nlohmann::json& r = out.report;
  r = mesh_stats_json(s, p.tiles, p.units, solid);
  const nlohmann::json periodic = periodic_surface_json(phi);
  const int cells = p.tiles[0] * p.tiles[1] * p.tiles[2];
  const double box = cells * std::pow(p.cell_size, 3);
  const double l2 = p.cell_size * p.cell_size;
  add_part_keys(r, p, n, periodic, mesh_seconds);
  if (solid) r["topology"] = part_topology_json(topology, p.units);
  if (p.solid == SolidKind::kSurface) {
    r["area_per_cell"] = s.area / cells / l2;
    r["area_per_cell_units"] = "unit cell edge^2";
  }
  if (p.solid == SolidKind::kNetwork) {
    double frac = sharp_volume_fraction(phi);  // as report.json volume_fraction
    if (p.other_phase) frac = 1.0 - frac;
    r["volume_fraction_mesh"] = s.volume / box;
    r["volume_fraction_field"] = frac;
  }
  if (p.solid == SolidKind::kSheet) {
    // Mean wall thickness = sheet volume / mid-surface area (the box holds whole periods), and
    // the Steiner-corrected t solving V = A t + (pi chi / 6) t^3 (per cell, unit-cell units).
    const double v_cell = s.volume / box, a_cell = periodic["area"].get<double>();
    const double chi = periodic["euler_characteristic"].get<double>();
    double t = v_cell / a_cell;
    for (int it = 0; it < 50; ++it) {
      const double g = a_cell * t + std::numbers::pi * chi / 6 * t * t * t - v_cell;
      t -= g / (a_cell + std::numbers::pi * chi / 2 * t * t);
    }
    r["volume_fraction_mesh"] = v_cell;
    r["sheet"] = {{"thickness_target", p.thickness},
                  {"thickness_mean", v_cell / a_cell * p.cell_size},
                  {"thickness_steiner", t * p.cell_size},
                  {"level_sets", "signed distance d = +-T/2 to the phi = 1/2 surface mesh"},
                  {"units", p.units}};
  }
  return out;
}

}  // namespace cmcsurf
