#include "mesh/scaffold_part.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>

#include "common/wall_clock.h"
#include "mesh/morphometry.h"
#include "mesh/shape.h"

namespace cmcsurf {

namespace {

constexpr int kMaxSolveIterations = 12;
// Voxels per cell edge for the local thickness, at least: a 0.1-cell wall is 6 voxels.
constexpr int kMorphometryGrid = 64;
// Above this many lattice nodes (256^3) the part itself is not measured: about 30 bytes a node
// and one distance transform per ball radius; its unit cell's measures stand.
constexpr std::size_t kMaxPartMorphometryNodes = 16'777'216;
// A network part misses its porosity only through the box trimming the lattice (a few 1e-4
// for whole cells); past this its level is shifted to hit the target.
constexpr double kNetworkPorosityTol = 1e-3;

struct Evaluation {
  double level = 0.0;
  double porosity = 0.0;
  double area = 0.0;
  PartTopology topology;
  TriMesh mesh;
};

Evaluation evaluate(PartLattice& lat, double level, bool keep_fragments) {
  Evaluation e;
  e.level = level;
  e.topology = clean_part(lat, level, keep_fragments);
  e.mesh = mesh_part(lat, level);
  e.porosity = 1.0 - mesh_volume(e.mesh) / lat.porosity_volume();
  e.area = mesh_area(e.mesh);
  return e;
}

// Wall thickness t (unit cells) of a sheet of volume fraction s around a surface of area A and
// Euler characteristic chi per cell: A t + (pi chi / 6) t^3 = s (Steiner's formula).
double steiner_thickness(double s, double area, double chi) {
  double t = s / area;
  for (int it = 0; it < 50; ++it) {
    const double g = area * t + std::numbers::pi * chi / 6 * t * t * t - s;
    t -= g / (area + std::numbers::pi * chi / 2 * t * t);
  }
  return t;
}

// The design's solid on one unit cell: {transform(g) > level}, g the member (network) or the
// signed distance to its surface (sheet, at the Steiner thickness of d.porosity).
struct CellSolid {
  Field distance;  // empty for a network
  std::function<double(double)> transform = [](double v) { return v - 0.5; };
  double level = 0.0;
  nlohmann::json sheet;
};

CellSolid cell_solid(const Field& phi, const ScaffoldDesign& d) {
  CellSolid cs;
  if (d.solid != SolidKind::kSheet) return cs;
  const nlohmann::json periodic = periodic_surface_json(phi);
  const double area = periodic["area"].get<double>();
  const double chi = periodic["euler_characteristic"].get<double>();
  const double t = steiner_thickness(1.0 - d.porosity, area, chi);
  if (!(t > 0.0 && t < 0.5))
    throw std::invalid_argument(fmt::format(
        "porosity {}: a sheet of that porosity is {:.3g} cells thick; accepted for a sheet: "
        "walls thinner than half a cell", d.porosity, t));
  cs.distance = signed_distance(phi, std::min(0.5, t + 4.0 / phi.n()));
  cs.transform = [](double v) { return -std::abs(v); };
  cs.level = -0.5 * t;
  cs.sheet = {{"thickness_steiner", t * d.cell_size}};
  return cs;
}

}  // namespace

double member_volume_fraction(const ScaffoldDesign& d) {
  return d.solid == SolidKind::kNetwork ? 1.0 - d.porosity : 0.5;
}

namespace {

// The part from its sampled lattice: the level solved for the porosity (a sheet always, a
// network only past kNetworkPorosityTol), the percolation check, decimation, and the report
// of the mesh as written (with report.seconds of these stages); the morphometry is the
// caller's. final_level: the level of the part returned.
ScaffoldPart finish_part(PartLattice& lat, double level, const ScaffoldDesign& d, int n,
                         nlohmann::json sheet, double& final_level,
                         const DecimateProgress& progress) {
  ScaffoldPart out;
  nlohmann::json& r = out.report;
  double slope = 0.0;  // d porosity / d level, 0: unknown
  auto t0 = std::chrono::steady_clock::now();
  // The porosity: the sheet's level (its half thickness) is solved by Newton then secant
  // steps on the part's own mesh; a network keeps the CMC level unless trimming moved it.
  Evaluation e = evaluate(lat, level, d.keep_fragments);
  const PartTopology at_member_level = e.topology;
  const double porosity_at_member_level = e.porosity;
  const double tol = d.solid == SolidKind::kSheet ? d.porosity_tol : kNetworkPorosityTol;
  int iterations = 1;  // part meshes evaluated
  if (std::abs(e.porosity - d.porosity) > tol) {
    // Sheet: a level step moves both walls by cell_size per unit, over the mesh's area.
    if (d.solid == SolidKind::kSheet) slope = e.area * d.cell_size / lat.porosity_volume();
    double next = slope > 0 ? level - (e.porosity - d.porosity) / slope : level + 1e-3;
    // A network's level stays inside the lattice's values: beyond them the part is all solid
    // or empty, and a secant step on a flat porosity (a field that no level thickens) got there.
    const auto [a_lo, a_hi] = std::minmax_element(lat.a.begin(), lat.a.end());
    const double margin = 0.01 * (double(*a_hi) - double(*a_lo));
    double last_level = e.level, last_porosity = e.porosity;  // the secant's other point
    while (iterations < kMaxSolveIterations) {
      if (d.solid == SolidKind::kNetwork)
        next = std::clamp(next, double(*a_lo) + margin, double(*a_hi) - margin);
      Evaluation cur = evaluate(lat, next, d.keep_fragments);
      ++iterations;
      const double secant = (cur.porosity - last_porosity) / (cur.level - last_level);
      last_level = cur.level, last_porosity = cur.porosity;
      const double err = cur.porosity - d.porosity;
      if (std::abs(err) <= std::abs(e.porosity - d.porosity)) e = std::move(cur);  // the best
      if (std::abs(err) <= d.porosity_tol) break;
      if (!(std::abs(secant) > 0) || !std::isfinite(secant)) break;
      next = last_level - err / secant;
      if (d.solid == SolidKind::kSheet) next = std::min(next, -0.5 / n);  // a wall of at least h
    }
    // The lattice's fragment marks are the last level's: those of the best again.
    if (e.level != last_level) e = evaluate(lat, e.level, d.keep_fragments);
  }
  const double solve_seconds = seconds_since(t0);
  const PartTopology& topo = e.topology;
  // Fragment removal may not move the porosity off its target unseen (a member in pieces):
  // fragments removed at the member's level or the solved one, and the target missed.
  const bool cut_last = topo.fragments > 0;
  const PartTopology& cut = cut_last ? topo : at_member_level;
  if (cut.fragments_removed && cut.fragments > 0 &&
      std::abs(e.porosity - d.porosity) > kNetworkPorosityTol)
    throw FragmentRemovalError(fmt::format(
        "removing {} fragments ({:.4g} {}^3 of {} solid pieces) leaves porosity {:.4f} against "
        "the target {}, more than {:g} off, and no level brings it back ({:.4f} at the last "
        "try), so nothing was written: the solid is not one connected lattice at this porosity "
        "(another topology, or a skin or box that cuts it apart). Choose another --porosity or "
        "--surface; --keep-fragments keeps every piece",
        cut.fragments, cut.fragment_volume, d.units, cut.solid_components,
        cut_last ? e.porosity : porosity_at_member_level, d.porosity, kNetworkPorosityTol,
        e.porosity));
  if (!lat.clip.empty() && lat.skin.empty() && topo.closed_pores > 0)
    throw ClosedCellError(fmt::format(
        "closed-cell part: {} pores inside the shape ({:.4g} {}^3) do not reach its surface; "
        "powder or resin could not be cleared out, so nothing was written. Raise --porosity "
        "or use another --surface.",
        topo.closed_pores, topo.closed_pore_volume, d.units));
  if (!topo.percolates()) {
    std::string axes;
    for (int c = 0; c < 3; ++c)
      if (!topo.pore_percolates[c]) axes += std::string(axes.empty() ? "" : ", ") + "xyz"[c];
    throw ClosedCellError(fmt::format(
        "closed-cell part: the pore space does not connect the opposite box faces along {} "
        "({} pore components, {} closed); powder or resin could not be cleared out, so "
        "nothing was written. Raise --porosity, use a larger --size, or another --surface.",
        axes, topo.pore_components, topo.closed_pores));
  }

  // Mesh size control.
  const std::size_t triangles_full = e.mesh.triangles.size();
  const bool decimate = d.decimate.max_triangles > 0 || d.decimate.tolerance > 0;
  nlohmann::json decimation;
  if (decimate) {
    Decimated dm = decimate_solid(e.mesh, d.decimate, progress);
    decimation = decimated_json(dm, d.decimate, d.units);
    if (!dm.within_budget)
      out.warnings.push_back(fmt::format(
          "decimation: {} triangles for a budget of {} (every smaller mesh failed the closed/"
          "manifold/one-piece/volume checks)", dm.triangles_after, d.decimate.max_triangles));
    e.mesh = std::move(dm.mesh);
  }

  // Measures of the mesh as written.
  const MeshStats s = analyze_mesh(e.mesh);
  r = mesh_stats_json(s, {1, 1, 1}, d.units, true);
  r.erase("v_minus_e_plus_f_per_cell");
  const double porosity = 1.0 - s.volume / lat.porosity_volume();
  // The warning is about the part as written (decimation moves the volume by up to 0.5 %).
  if (std::abs(porosity - d.porosity) > kNetworkPorosityTol) {
    if (std::abs(e.porosity - d.porosity) > kNetworkPorosityTol)
      out.warnings.push_back(fmt::format(
          "porosity {:.4f} misses the target {} by more than 1e-3: no {} level reaches it{}",
          porosity, d.porosity, solid_kind_name(d.solid),
          lat.skin.empty() ? "" : " (the --skin alone may take that much of the volume)"));
    else
      out.warnings.push_back(fmt::format(
          "porosity {:.4f} misses the target {} by more than 1e-3 after decimation ({:.4f} "
          "before): a larger --max-triangles or a smaller --tolerance keeps it closer",
          porosity, d.porosity, e.porosity));
  }
  r["design"] = {{"porosity", d.porosity},
                 {"solid", solid_kind_name(d.solid)},
                 {"cell_size", d.cell_size},
                 {"size", d.size},
                 {"units", d.units},
                 {"member_volume_fraction", member_volume_fraction(d)}};
  r["porosity"] = porosity;
  r["porosity_error"] = porosity - d.porosity;
  r["porosity_unsimplified"] = e.porosity;
  r["grid"] = n;
  r["lattice_nodes"] = lat.nodes;
  r["lattice_spacing"] = lat.spacing;
  r["cells"] = {d.size[0] / d.cell_size, d.size[1] / d.cell_size, d.size[2] / d.cell_size};
  r["triangles_unsimplified"] = triangles_full;
  r["solve"] = {{"iterations", iterations}, {"level", e.level}};
  if (d.solid == SolidKind::kSheet) {
    sheet["thickness"] = -2.0 * e.level * d.cell_size;
    sheet["units"] = d.units;
    sheet["level_sets"] = "signed distance d = +-thickness/2 to the phi = 1/2 surface mesh";
    r["sheet"] = sheet;
  } else {
    r["solve"]["level_shift"] = e.level;
    r["solve"]["note"] = "phi level shift from 1/2 (0 unless trimming the box moved the porosity "
                         "by more than 1e-3)";
  }
  r["topology"] = part_topology_json(topo, d.units);
  if (topo.fragments > 0 && !topo.fragments_removed)
    out.warnings.push_back(fmt::format("{} fragments cut off by the box were kept "
                                       "(--keep-fragments), {:.4g} {}^3 in all",
                                       topo.fragments, topo.fragment_volume, d.units));
  if (topo.closed_pores > 0)
    out.warnings.push_back(fmt::format("{} closed pores ({:.4g} {}^3) inside the part",
                                       topo.closed_pores, topo.closed_pore_volume, d.units));
  if (decimate) r["decimation"] = decimation;

  r["seconds"] = {{"solve_clean_mesh", solve_seconds},
                  {"topology_last", topo.seconds},
                  {"decimate", decimate ? decimation["seconds"].get<double>() : 0.0}};
  final_level = e.level;
  out.mesh = std::move(e.mesh);
  return out;
}

// Local thickness of both phases on one unit cell of g at >= kMorphometryGrid voxels per edge
// (the field interpolated), solid = {transform(g) > level}; warnings under d.min_feature.
nlohmann::json cell_morphometry(const Field& g, const std::function<double(double)>& transform,
                                double level, const ScaffoldDesign& d,
                                std::vector<std::string>& warnings) {
  nlohmann::json morph;
  const int n = g.n();
  const int refine = (kMorphometryGrid + n - 1) / n, m = n * refine;
  const PartLattice cell = sample_part(g, {d.cell_size, d.cell_size, d.cell_size}, d.cell_size,
                                       transform, refine);
  std::vector<std::uint8_t> solid(cell.count()), pore(cell.count());
  for (std::size_t id = 0; id < cell.count(); ++id) {
    solid[id] = cell.a[id] > float(level);
    pore[id] = !solid[id];
  }
  const double voxel = d.cell_size / m;
  const ThicknessStats wall = thickness_stats(local_thickness(solid, m), solid, voxel);
  const ThicknessStats pores = thickness_stats(local_thickness(pore, m), pore, voxel);
  morph["wall_thickness"] = thickness_json(wall, d.units);
  morph["pore_size"] = thickness_json(pores, d.units);
  std::array<double, 3> throat = throat_diameter(pore, m);
  for (double& t : throat) t *= voxel;
  morph["throat"] = {{"diameter", throat},
                     {"min", *std::min_element(throat.begin(), throat.end())},
                     {"units", d.units},
                     {"note", "largest ball that passes through the pore space along x, y, z "
                              "(the bottleneck of its distance map, periodic cell); 0: the "
                              "pores do not percolate along that axis"}};
  morph["method"] = "local thickness (largest inscribed ball containing each voxel) on the "
                    "periodic unit cell (the field interpolated to >= 64^3 voxels), exact "
                    "Euclidean distance transform; diameters, within one voxel; p5, p50, p95: "
                    "percentiles over the wall's (solid's) or the pore space's volume";
  morph["voxel"] = voxel;
  if (d.min_feature > 0) {
    morph["min_feature"] = d.min_feature;
    if (wall.min < d.min_feature)
      warnings.push_back(fmt::format("thinnest wall {:.4g} {} is below --min-feature {}",
                                     wall.min, d.units, d.min_feature));
    if (pores.min < d.min_feature)
      warnings.push_back(fmt::format("narrowest pore {:.4g} {} is below --min-feature {}",
                                     pores.min, d.units, d.min_feature));
  }
  return morph;
}

// Wall thickness, pore size and throat of the part as built, on its lattice (not periodic):
// the solid at `level` without its removed fragments, the pores within the box (or the shape).
// Beyond the box a wall is cut (outside) and a pore goes on. Node spacings differ by the
// rounding of the box to whole nodes (well under 1 %); their mean is the voxel.
nlohmann::json part_morphometry(const PartLattice& lat, double level, const ScaffoldDesign& d) {
  // Every stride-th node: the part at about kMorphometryGrid voxels per cell at most, the
  // cell's own resolution, so that its cost stays that of a grid-64 lattice.
  const double per_cell = d.cell_size / lat.spacing[0];
  const int stride = std::max(1, int(std::floor(per_cell / kMorphometryGrid + 1e-9)));
  std::array<int, 3> dims;
  for (int c = 0; c < 3; ++c) dims[c] = (lat.nodes[c] + stride - 1) / stride;
  const std::size_t count = std::size_t(dims[0]) * dims[1] * dims[2];
  if (count > kMaxPartMorphometryNodes)
    return {{"measured", false},
            {"note", fmt::format("not measured: the part's lattice has {} nodes, more than {} "
                                 "(its unit cell's measures stand)", count,
                                 kMaxPartMorphometryNodes)}};
  std::vector<std::uint8_t> solid(count), pore(count);
  std::size_t at = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i, ++at) {
        const std::size_t id = lat.index(i * stride, j * stride, k * stride);
        solid[at] = lat.value(id, level) > 0 && (lat.removed.empty() || !lat.removed[id]);
        pore[at] = !solid[at] && (lat.clip.empty() || lat.clip[id] > 0);
      }
  const double voxel = stride * (lat.spacing[0] + lat.spacing[1] + lat.spacing[2]) / 3.0;
  // Radii in quarter voxels: diameters at most half a voxel short, half the transforms.
  constexpr double kPartRadiusStep = 0.25;
  const ThicknessStats wall = thickness_stats(
      box_local_thickness(solid, dims, true, kPartRadiusStep), solid, voxel);
  const ThicknessStats pores = thickness_stats(
      box_local_thickness(pore, dims, false, kPartRadiusStep), pore, voxel);
  nlohmann::json m = {{"measured", true},
                      {"wall_thickness", thickness_json(wall, d.units)},
                      {"pore_size", thickness_json(pores, d.units)},
                      {"voxel", voxel},
                      {"nodes", dims},
                      {"stride", stride}};
  if (lat.clip.empty()) {
    std::array<double, 3> throat = box_throat_diameter(pore, dims);
    for (double& t : throat) t *= voxel;
    m["throat"] = {{"diameter", throat},
                   {"min", *std::min_element(throat.begin(), throat.end())},
                   {"units", d.units},
                   {"note", "largest ball that passes through the part's pores from each box "
                            "face to the opposite one, along x, y, z"}};
  }
  m["method"] = "local thickness on the part's lattice (the box as trimmed, or the shape), at "
                "the lattice spacing cell size / grid (every stride-th node past 64 voxels per "
                "cell), not periodic: a wall ends where the box cuts it, a pore goes on past "
                "the box; diameters within one voxel; p5, p50, p95: percentiles over the "
                "wall's (solid's) or the pore space's volume";
  return m;
}

nlohmann::json surface_measures(const ScaffoldPart& part, const PartLattice& lat,
                                const std::string& units) {
  const double area = part.report["area"].get<double>(),
               volume = part.report["volume"].get<double>();
  return {{"specific_surface", area / volume},
          {"specific_surface_units", "1/" + units},
          {"surface_density", area / lat.porosity_volume()},
          {"note", "specific_surface = mesh area / solid volume, surface_density = mesh area / "
                   "box volume (cut faces included)"}};
}

// The porosity profile along the axis, per cell: the target (target_solid per node layer) and
// the fraction of each layer's nodes outside the solid {value > level}.
nlohmann::json porosity_profile(const PartLattice& lat, double level, int axis,
                                const std::vector<double>& target_solid, const ScaffoldDesign& d) {
  nlohmann::json profile = nlohmann::json::array();
  const int layers = lat.nodes[axis];
  std::vector<std::size_t> inside(layers, 0), in_part(layers, 0);  // a shape: its nodes only
  for (int k = 0; k < lat.nodes[2]; ++k)
    for (int j = 0; j < lat.nodes[1]; ++j)
      for (int i = 0; i < lat.nodes[0]; ++i) {
        const std::size_t id = lat.index(i, j, k);
        const int at[3] = {i, j, k};
        inside[at[axis]] += lat.value(id, level) > 0.0 && !lat.removed[id];
        in_part[at[axis]] += lat.clip.empty() || lat.clip[id] > 0;
      }
  const int slabs = std::max(1, int(std::lround(d.size[axis] / d.cell_size)));
  for (int b = 0; b < slabs; ++b) {
    const int q0 = b * layers / slabs, q1 = (b + 1) * layers / slabs;
    double solid = 0.0, part = 0.0, want = 0.0;
    for (int q = q0; q < q1; ++q) solid += inside[q], part += in_part[q], want += target_solid[q];
    profile.push_back({{"from", q0 * lat.spacing[axis]},
                       {"to", q1 * lat.spacing[axis]},
                       {"porosity_target", 1.0 - want / (q1 - q0)},
                       {"porosity_nodes", part > 0 ? 1.0 - solid / part : 1.0}});
  }
  return profile;
}

// --min-feature once over a graded part's cells: the thinnest wall and pore of any.
void warn_min_feature(const nlohmann::json& cells, const ScaffoldDesign& d,
                      std::vector<std::string>& warnings) {
  if (!(d.min_feature > 0) || cells.empty()) return;
  for (const char* key : {"wall_thickness", "pore_size"}) {
    const auto thinnest = std::min_element(cells.begin(), cells.end(), [&](auto& a, auto& b) {
      return a[key]["min"].template get<double>() < b[key]["min"].template get<double>();
    });
    const double v = (*thinnest)[key]["min"].get<double>();
    if (v < d.min_feature)
      warnings.push_back(fmt::format(
          "{} {:.4g} {} (cell at porosity {:.2f}) is below --min-feature {}",
          key == std::string("wall_thickness") ? "thinnest wall" : "narrowest pore", v, d.units,
          (*thinnest)["porosity"].get<double>(), d.min_feature));
  }
}

// The lattice's box for a shape: its bounding box with two grid spacings around it, so that
// the solid ends on the shape's surface rather than on the box.
Vec3 shape_box(const ShapeFill& shape, const ScaffoldDesign& d, int n) {
  const MeshStats ss = analyze_mesh(shape.mesh);
  const double margin = 2.0 * d.cell_size / n;
  Vec3 size;
  for (int c = 0; c < 3; ++c) size[c] = ss.max[c] - ss.min[c] + 2 * margin;
  return size;
}

// Cuts a lattice sampled on shape_box to the shape (origin, clip, skin, the reference volume);
// returns FILE.json's `shape`.
// depth: the distance is also exact that far inside the skin (a fill graded by depth).
nlohmann::json cut_to_shape(PartLattice& lat, const ShapeFill& shape_fill,
                            const ScaffoldDesign& d, int n, double depth = 0.0) {
  const ShapeFill* shape = &shape_fill;
  const MeshStats ss = analyze_mesh(shape->mesh);
  const double margin = 2.0 * d.cell_size / n;
  for (int c = 0; c < 3; ++c) lat.origin[c] = ss.min[c] - margin;
  const std::vector<float> sdf =
      shape_distance(shape->mesh, lat, shape->skin + 4.0 * margin + depth);
  // Distances into a's units (unit cells): the solid is also {sdf < 0}, and the skin
  // {-skin < sdf < 0} is solid whatever the lattice.
  const double k = 1.0 / d.cell_size;
  lat.clip.resize(sdf.size());
  for (std::size_t id = 0; id < sdf.size(); ++id) lat.clip[id] = float(-k * sdf[id]);
  if (shape->skin > 0) {
    lat.skin.resize(sdf.size());
    for (std::size_t id = 0; id < sdf.size(); ++id)
      lat.skin[id] = float(k * std::min(-double(sdf[id]), sdf[id] + shape->skin));
  }
  // The shape's volume: its triangles' (exact) unless shells may overlap, which those would
  // count twice; then the union's as the lattice cuts it (within O(h^2) at edges).
  lat.reference_volume = std::abs(ss.volume);
  const bool overlap = shells_may_overlap(shape->mesh);
  if (overlap) {
    PartLattice inside;
    inside.nodes = lat.nodes, inside.spacing = lat.spacing, inside.size = lat.size;
    inside.origin = lat.origin, inside.a = lat.clip;
    lat.reference_volume = mesh_volume(mesh_part(inside, 0.0));
  }
  return {{"volume", lat.reference_volume},
           {"volume_triangles", std::abs(ss.volume)},
           {"shells_may_overlap", overlap},
           {"bounding_box", {{"min", ss.min}, {"max", ss.max}}},
           {"triangles", ss.triangles},
           {"skin", shape->skin},
           {"units", d.units},
           {"method", "signed distance by OpenVDB meshToLevelSet (rebuilt: the union "
                      "of shells that may overlap) on the lattice's nodes; solid = "
                      "lattice solid within the shape, plus the skin; volume: "
                      "volume_triangles (their signed sum), or the union's on the "
                      "lattice when shells may overlap"}};
}

// Each node's place on a porosity ramp, 0 (porosity `from`) .. 1 (`to`): the middle of its
// layer along the axis, or its depth below the shape's surface past the skin over ramp.depth
// (lat.clip in cells, exact that deep: cut_to_shape's depth); the skin and outside are 0.
std::vector<float> ramp_place(const PartLattice& lat, const PorosityRamp& ramp,
                              const ScaffoldDesign& d, double skin) {
  std::vector<float> place(lat.count());
  const int layers = lat.nodes[ramp.axis];
  for (int k = 0; k < lat.nodes[2]; ++k)
    for (int j = 0; j < lat.nodes[1]; ++j)
      for (int i = 0; i < lat.nodes[0]; ++i) {
        const std::size_t id = lat.index(i, j, k);
        const int at[3] = {i, j, k};
        place[id] = ramp.by_surface
                        ? float(std::clamp((lat.clip[id] * d.cell_size - skin) / ramp.depth,
                                           0.0, 1.0))
                        : float((at[ramp.axis] + 0.5) / layers);
      }
  return place;
}

double ramp_porosity(const PorosityRamp& ramp, double place) {
  return ramp.from + (ramp.to - ramp.from) * place;
}

// The ramp's mean porosity over the part: the box's middle value, or over the shape's nodes.
double ramp_mean(const PartLattice& lat, const PorosityRamp& ramp,
                 const std::vector<float>& place) {
  if (lat.clip.empty()) return 0.5 * (ramp.from + ramp.to);
  double sum = 0.0, count = 0.0;
  for (std::size_t id = 0; id < lat.count(); ++id)
    if (lat.clip[id] > 0) sum += ramp_porosity(ramp, place[id]), count += 1.0;
  return count > 0 ? sum / count : 0.5 * (ramp.from + ramp.to);
}

// The porosity by depth below a shape's surface (past its skin): kDepthBands bands over
// ramp.depth and the core beyond, each with its nodes' mean target and the fraction of them
// outside the solid.
constexpr int kDepthBands = 4;
nlohmann::json depth_profile(const PartLattice& lat, double level, const PorosityRamp& ramp,
                             const std::vector<float>& place, const ScaffoldDesign& d,
                             double skin) {
  std::array<double, kDepthBands + 1> solid{}, count{}, want{};
  for (std::size_t id = 0; id < lat.count(); ++id) {
    const double below = lat.clip[id] * d.cell_size - skin;
    if (!(lat.clip[id] > 0) || below < 0) continue;  // outside, or in the skin
    const int b = std::min(kDepthBands, int(below / ramp.depth * kDepthBands));
    count[b] += 1.0;
    want[b] += ramp_porosity(ramp, place[id]);
    solid[b] += lat.value(id, level) > 0.0 && !lat.removed[id];
  }
  nlohmann::json profile = nlohmann::json::array();
  for (int b = 0; b <= kDepthBands; ++b)
    profile.push_back({{"depth_from", b * ramp.depth / kDepthBands},
                       {"depth_to", b < kDepthBands ? nlohmann::json((b + 1) * ramp.depth /
                                                                     kDepthBands)
                                                    : nlohmann::json()},
                       {"nodes", count[b]},
                       {"porosity_target", count[b] > 0 ? want[b] / count[b] : NAN},
                       {"porosity_nodes", count[b] > 0 ? 1.0 - solid[b] / count[b] : NAN}});
  return profile;
}

// FILE.json's `graded` keys that say how the ramp runs.
nlohmann::json ramp_json(const PorosityRamp& ramp, const ScaffoldDesign& d) {
  nlohmann::json g = {{"porosity_from", ramp.from}, {"porosity_to", ramp.to}};
  if (ramp.by_surface) {
    g["by"] = "surface";
    g["axis"] = nullptr;
    g["depth"] = ramp.depth;
    g["units"] = d.units;
    g["profile_note"] = "by depth below the shape's surface (past the skin): four bands over "
                        "`depth` and the core beyond (depth_to null), each the mean target and "
                        "the fraction of its lattice nodes outside the solid";
  } else {
    g["by"] = "axis";
    g["axis"] = std::string(1, "xyz"[ramp.axis]);
    g["profile_note"] = "per cell along the axis: the target and the fraction of lattice nodes "
                        "outside the solid";
  }
  return g;
}

void check_ramp_place(const PorosityRamp& ramp, const ShapeFill* shape) {
  if (ramp.by_surface && shape == nullptr)
    throw std::invalid_argument("a ramp by depth needs a shape (the depth below its surface)");
  if (ramp.by_surface && !(ramp.depth > 0.0 && std::isfinite(ramp.depth)))
    throw std::invalid_argument(fmt::format("the ramp's depth {} must be > 0", ramp.depth));
}

// `graded.profile`: per cell along the axis, or by depth below the shape's surface.
nlohmann::json graded_profile(const PartLattice& lat, double level, const PorosityRamp& ramp,
                              const std::vector<float>& place, const ScaffoldDesign& d,
                              const ShapeFill* shape) {
  if (ramp.by_surface) return depth_profile(lat, level, ramp, place, d, shape->skin);
  const int layers = lat.nodes[ramp.axis];
  std::vector<double> target(layers);
  for (int q = 0; q < layers; ++q)
    target[q] = 1.0 - ramp_porosity(ramp, (q + 0.5) / layers);
  return porosity_profile(lat, level, ramp.axis, target, d);
}

}  // namespace

ScaffoldPart design_scaffold(const Field& phi, const ScaffoldDesign& d, const ShapeFill* shape,
                             const DecimateProgress& progress) {
  if (!(d.porosity > 0.0 && d.porosity < 1.0))
    throw std::invalid_argument(fmt::format("porosity {} must be in (0, 1)", d.porosity));
  if (d.solid != SolidKind::kNetwork && d.solid != SolidKind::kSheet)
    throw std::invalid_argument("a scaffold's solid is network or sheet");
  const int n = phi.n();
  auto t0 = std::chrono::steady_clock::now();

  // The field sampled on the box and the level of the solid {a > level}.
  CellSolid cs = cell_solid(phi, d);
  const Field* g = cs.distance.n() > 0 ? &cs.distance : &phi;
  const std::function<double(double)> transform = cs.transform;
  const double level = cs.level;
  nlohmann::json sheet = cs.sheet;
  const double field_seconds = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  nlohmann::json shape_report;
  PartLattice lat = sample_part(*g, shape ? shape_box(*shape, d, n) : d.size, d.cell_size,
                                transform);
  if (shape != nullptr) shape_report = cut_to_shape(lat, *shape, d, n);
  const double sample_seconds = seconds_since(t0);

  double final_level = level;
  ScaffoldPart out = finish_part(lat, level, d, n, std::move(sheet), final_level, progress);
  nlohmann::json& r = out.report;
  // Morphometry on the periodic unit cell (the lattice's own walls and pores).
  nlohmann::json morph = surface_measures(out, lat, d.units);
  double morph_seconds = 0.0;
  if (d.morphometry) {
    t0 = std::chrono::steady_clock::now();
    morph.update(cell_morphometry(*g, transform, final_level, d, out.warnings));
    morph_seconds = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    morph["part"] = part_morphometry(lat, final_level, d);
    r["seconds"]["morphometry_part"] = seconds_since(t0);
  }
  r["morphometry"] = morph;
  if (shape != nullptr) {
    r["shape"] = shape_report;
    r["design"]["size"] = nullptr;
  }
  r["warnings"] = out.warnings;
  r["seconds"]["distance_field"] = field_seconds;
  r["seconds"]["sample"] = sample_seconds;
  r["seconds"]["morphometry"] = morph_seconds;
  return out;
}

ScaffoldPart design_graded_scaffold(const std::vector<GradedMember>& members,
                                    const ScaffoldDesign& d, const PorosityRamp& ramp,
                                    const DecimateProgress& progress, const ShapeFill* shape) {
  if (d.solid != SolidKind::kNetwork)
    throw std::invalid_argument("a graded scaffold is a network solid");
  if (members.size() < 2) throw std::invalid_argument("a graded scaffold needs two members");
  for (double p : {ramp.from, ramp.to})
    if (!(p > 0.0 && p < 1.0))
      throw std::invalid_argument(fmt::format("porosity {} must be in (0, 1)", p));
  if (ramp.axis < 0 || ramp.axis > 2) throw std::invalid_argument("ramp axis must be 0, 1 or 2");
  const int n = members[0].phi.n();
  for (std::size_t m = 1; m < members.size(); ++m) {
    if (members[m].phi.n() != n) throw std::invalid_argument("graded members must share one grid");
    if (!(members[m].volume_fraction > members[m - 1].volume_fraction))
      throw std::invalid_argument("graded members must be sorted by increasing volume fraction");
  }
  const double lo = members.front().volume_fraction, hi = members.back().volume_fraction;
  for (double p : {ramp.from, ramp.to})
    if (!(1.0 - p >= lo - ramp.fraction_tol && 1.0 - p <= hi + ramp.fraction_tol))
      throw std::invalid_argument(fmt::format(
          "porosity {}: outside the members' porosities [{:.6f}, {:.6f}]", p, 1.0 - hi, 1.0 - lo));
  check_ramp_place(ramp, shape);
  auto t0 = std::chrono::steady_clock::now();
  // The blend per node: the solid fraction 1 - porosity at the node's place on the ramp is
  // interpolated between the two members that bracket it (hat-function weights).
  PartLattice lat;
  std::vector<float> place;
  nlohmann::json shape_report;
  const Vec3 box = shape ? shape_box(*shape, d, n) : d.size;
  for (std::size_t m = 0; m < members.size(); ++m) {
    PartLattice one =
        sample_part(members[m].phi, box, d.cell_size, [](double v) { return v - 0.5; });
    if (m == 0) {
      lat = one;
      std::fill(lat.a.begin(), lat.a.end(), 0.0f);
      if (shape != nullptr)
        shape_report = cut_to_shape(lat, *shape, d, n, ramp.by_surface ? ramp.depth : 0.0);
      place = ramp_place(lat, ramp, d, shape ? shape->skin : 0.0);
    }
    const double here = members[m].volume_fraction;
    const double below = m > 0 ? members[m - 1].volume_fraction : NAN,
                 above = m + 1 < members.size() ? members[m + 1].volume_fraction : NAN;
    for (std::size_t id = 0; id < lat.count(); ++id) {
      const double a = std::clamp(1.0 - ramp_porosity(ramp, place[id]), lo, hi);
      float w = 0.0f;
      if (m > 0 && a >= below && a <= here) w = float((a - below) / (here - below));
      else if (m + 1 < members.size() && a >= here && a < above)
        w = float((above - a) / (above - here));
      else if (a == here) w = 1.0f;
      if (w != 0.0f) lat.a[id] += w * one.a[id];
    }
  }
  // A shape's mean porosity: the ramp's weighted by its nodes (for an axis, its sections).
  ScaffoldDesign mean = d;
  mean.porosity = ramp_mean(lat, ramp, place);
  const double sample_seconds = seconds_since(t0);
  double final_level = 0.0;
  ScaffoldPart out = finish_part(lat, 0.0, mean, n, nlohmann::json(), final_level, progress);
  nlohmann::json& r = out.report;
  if (shape != nullptr) {
    r["shape"] = shape_report;
    r["design"]["size"] = nullptr;
  }
  const nlohmann::json profile = graded_profile(lat, final_level, ramp, place, d, shape);
  nlohmann::json fractions = nlohmann::json::array(), cells = nlohmann::json::array();
  double morph_seconds = 0.0;
  t0 = std::chrono::steady_clock::now();
  // --min-feature is checked once over the members (the thinnest wall and pore of any).
  ScaffoldDesign each = d;
  each.min_feature = 0.0;
  std::vector<std::string> none;
  for (const GradedMember& m : members) {
    fractions.push_back(m.volume_fraction);
    if (d.morphometry) {
      nlohmann::json c = cell_morphometry(m.phi, [](double v) { return v - 0.5; }, final_level,
                                          each, none);
      c["porosity"] = 1.0 - m.volume_fraction;
      c.erase("method");
      cells.push_back(c);
    }
  }
  if (d.morphometry) warn_min_feature(cells, d, out.warnings);
  morph_seconds = seconds_since(t0);
  r["design"]["porosity"] = nullptr;
  r["graded"] = ramp_json(ramp, d);
  r["graded"].update({{"porosity_mean", mean.porosity},  // over the box, or the shape's nodes
                      {"member_volume_fractions", fractions},
                      {"blend", "phi - 1/2 of the two members bracketing the local solid "
                                "fraction, weights linear in it, per node (its layer along the "
                                "axis, or its depth)"},
                      {"profile", profile}});
  nlohmann::json morph = surface_measures(out, lat, d.units);
  if (d.morphometry) morph["members"] = cells;
  if (d.morphometry && d.min_feature > 0) morph["min_feature"] = d.min_feature;
  if (d.morphometry) {
    // The graded part as built: its thinnest wall is where the ramp puts it, not a member.
    const auto t_part = std::chrono::steady_clock::now();
    morph["part"] = part_morphometry(lat, final_level, d);
    r["seconds"]["morphometry_part"] = seconds_since(t_part);
  }
  r["morphometry"] = morph;
  r["warnings"] = out.warnings;
  r["seconds"]["sample"] = sample_seconds;
  r["seconds"]["morphometry"] = morph_seconds;
  return out;
}

ScaffoldPart design_graded_sheet(const Field& phi, const ScaffoldDesign& d,
                                 const PorosityRamp& ramp, const DecimateProgress& progress,
                                 const ShapeFill* shape) {
  if (d.solid != SolidKind::kSheet)
    throw std::invalid_argument("a graded sheet is a sheet solid");
  for (double p : {ramp.from, ramp.to})
    if (!(p > 0.0 && p < 1.0))
      throw std::invalid_argument(fmt::format("porosity {} must be in (0, 1)", p));
  if (ramp.axis < 0 || ramp.axis > 2) throw std::invalid_argument("ramp axis must be 0, 1 or 2");
  check_ramp_place(ramp, shape);
  const int n = phi.n();
  auto t0 = std::chrono::steady_clock::now();
  // Each node's wall from Steiner's formula at its porosity, offset from the mean wall's:
  // a = -|d| + (t_q - t_mean) / 2, so that {a > -t_mean / 2} is {|d| < t_q / 2} and the part's
  // level solve shifts every node's wall by the same amount to meet the mean porosity.
  const nlohmann::json periodic = periodic_surface_json(phi);
  const double area = periodic["area"].get<double>();
  const double chi = periodic["euler_characteristic"].get<double>();
  auto wall = [&](double porosity) {
    const double t = steiner_thickness(1.0 - porosity, area, chi);
    if (!(t > 0.0 && t < 0.5))
      throw std::invalid_argument(fmt::format(
          "porosity {}: a sheet of that porosity is {:.3g} cells thick; accepted for a sheet: "
          "walls thinner than half a cell", porosity, t));
    return t;
  };
  const double t_from = wall(ramp.from), t_to = wall(ramp.to);
  const Field distance = signed_distance(phi, std::min(0.5, std::max(t_from, t_to) + 4.0 / n));
  const double field_seconds = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  PartLattice lat = sample_part(distance, shape ? shape_box(*shape, d, n) : d.size, d.cell_size,
                                [](double v) { return -std::abs(v); });
  nlohmann::json shape_report;
  if (shape != nullptr)
    shape_report = cut_to_shape(lat, *shape, d, n, ramp.by_surface ? ramp.depth : 0.0);
  const std::vector<float> place = ramp_place(lat, ramp, d, shape ? shape->skin : 0.0);
  const double mean_porosity = ramp_mean(lat, ramp, place);
  const double t_mean = wall(mean_porosity);
  // The wall along the ramp, tabulated: Steiner's thickness is smooth in the porosity, so a
  // linear interpolant of 1024 intervals is exact to far below a lattice spacing.
  constexpr int kWallTable = 1024;
  std::vector<double> offset(kWallTable + 1);
  for (int q = 0; q <= kWallTable; ++q)
    offset[q] = 0.5 * (wall(ramp_porosity(ramp, double(q) / kWallTable)) - t_mean);
  for (std::size_t id = 0; id < lat.count(); ++id) {
    const double x = place[id] * kWallTable;
    const int q = std::min(kWallTable - 1, int(x));
    lat.a[id] += float(offset[q] + (x - q) * (offset[q + 1] - offset[q]));
  }
  const double sample_seconds = seconds_since(t0);
  ScaffoldDesign mean = d;
  mean.porosity = mean_porosity;
  double final_level = -0.5 * t_mean;
  ScaffoldPart out = finish_part(lat, final_level, mean, n,
                                 {{"thickness_steiner_from", t_from * d.cell_size},
                                  {"thickness_steiner_to", t_to * d.cell_size}},
                                 final_level, progress);
  nlohmann::json& r = out.report;
  // The solve's shift of every wall: thickness_q = t_q - 2 (level + t_mean / 2).
  const double shift = -2.0 * (final_level + 0.5 * t_mean);
  r["sheet"]["thickness_from"] = (t_from + shift) * d.cell_size;
  r["sheet"]["thickness_to"] = (t_to + shift) * d.cell_size;
  r["sheet"]["thickness_note"] = ramp.by_surface
                                     ? "thickness: at the mean porosity's; thickness_from at the "
                                       "shape's surface, thickness_to at the depth and deeper"
                                     : "thickness: the mean layer's; thickness_from and _to at "
                                       "the ends of the axis";
  const nlohmann::json profile = graded_profile(lat, final_level, ramp, place, d, shape);
  // The wall and pores of the cells at the two ends.
  nlohmann::json cells = nlohmann::json::array();
  t0 = std::chrono::steady_clock::now();
  if (d.morphometry) {
    ScaffoldDesign each = d;
    each.min_feature = 0.0;
    std::vector<std::string> none;
    for (const auto& [p, t] : {std::pair{ramp.from, t_from}, {ramp.to, t_to}}) {
      nlohmann::json c = cell_morphometry(distance, [](double v) { return -std::abs(v); },
                                          -0.5 * (t + shift), each, none);
      c["porosity"] = p;
      c.erase("method");
      cells.push_back(c);
    }
    warn_min_feature(cells, d, out.warnings);
  }
  const double morph_seconds = seconds_since(t0);
  r["design"]["porosity"] = nullptr;
  r["graded"] = ramp_json(ramp, d);
  r["graded"].update({{"porosity_mean", mean_porosity},
                      {"blend", "the sheet's wall thickness per node (its layer along the axis, "
                                "or its depth), from Steiner's formula at its porosity, all "
                                "shifted together to meet the mean porosity"},
                      {"profile", profile}});
  if (shape != nullptr) {
    r["shape"] = shape_report;
    r["design"]["size"] = nullptr;
  }
  nlohmann::json morph = surface_measures(out, lat, d.units);
  if (d.morphometry) morph["members"] = cells;
  if (d.morphometry && d.min_feature > 0) morph["min_feature"] = d.min_feature;
  if (d.morphometry) {
    // The graded part as built: its thinnest wall is where the ramp puts it, not a member.
    const auto t_part = std::chrono::steady_clock::now();
    morph["part"] = part_morphometry(lat, final_level, d);
    r["seconds"]["morphometry_part"] = seconds_since(t_part);
  }
  r["morphometry"] = morph;
  r["warnings"] = out.warnings;
  r["seconds"]["distance_field"] = field_seconds;
  r["seconds"]["sample"] = sample_seconds;
  r["seconds"]["morphometry"] = morph_seconds;
  return out;
}

ScaffoldPart design_graded_cell_scaffold(const Field& phi, const ScaffoldDesign& d,
                                         const CellSizeRamp& ramp,
                                         const DecimateProgress& progress) {
  if (d.solid != SolidKind::kNetwork)
    throw std::invalid_argument("a graded cell size is done for a network solid only");
  if (!(ramp.from > 0 && ramp.to > 0 && ramp.from != ramp.to) || ramp.axis < 0 || ramp.axis > 2 ||
      !(ramp.transition > 0 && ramp.transition <= 1))
    throw std::invalid_argument("a graded cell size needs two different cell sizes > 0");
  const int n = phi.n();
  auto t0 = std::chrono::steady_clock::now();
  const auto transform = [](double v) { return v - 0.5; };
  const double fine = std::min(ramp.from, ramp.to), coarse = std::max(ramp.from, ramp.to);
  PartLattice lat = sample_part(phi, d.size, fine, transform);
  PartLattice other = lat;  // the same nodes, the other cell size
  fill_part(other, phi, coarse, transform);
  const std::vector<float>& at_from = ramp.from == fine ? lat.a : other.a;
  const std::vector<float>& at_to = ramp.from == fine ? other.a : lat.a;
  // Smoothstep weight of `to` per node layer along the axis (0 .. 1 over the transition).
  const int layers = lat.nodes[ramp.axis];
  std::vector<double> w(layers);
  for (int q = 0; q < layers; ++q) {
    const double s = (q + 0.5) / layers;
    const double u = std::clamp((s - 0.5 + 0.5 * ramp.transition) / ramp.transition, 0.0, 1.0);
    w[q] = u * u * (3.0 - 2.0 * u);
  }
  std::vector<float> blended(lat.count());
  for (int k = 0; k < lat.nodes[2]; ++k)
    for (int j = 0; j < lat.nodes[1]; ++j)
      for (int i = 0; i < lat.nodes[0]; ++i) {
        const int at[3] = {i, j, k};
        const std::size_t id = lat.index(i, j, k);
        const double t = w[at[ramp.axis]];
        blended[id] = float((1.0 - t) * at_from[id] + t * at_to[id]);
      }
  lat.a = std::move(blended);
  other = PartLattice();
  const double sample_seconds = seconds_since(t0);

  ScaffoldDesign fine_design = d;
  fine_design.cell_size = fine;
  double final_level = 0.0;
  ScaffoldPart out =
      finish_part(lat, 0.0, fine_design, n, nlohmann::json(), final_level, progress);
  nlohmann::json& r = out.report;
  // design.cell_size and cells stay the finer cell's (the lattice's); the ends beside them.
  r["design"]["cell_size_from"] = ramp.from;
  r["design"]["cell_size_to"] = ramp.to;
  const std::vector<double> target(layers, 1.0 - d.porosity);
  r["graded_cell_size"] = {
      {"axis", std::string(1, "xyz"[ramp.axis])},
      {"cell_size_from", ramp.from},
      {"cell_size_to", ramp.to},
      {"transition", ramp.transition},
      {"blend", "phi - 1/2 of the member at each cell size on the finer one's nodes, weights a "
                "smoothstep over the middle `transition` of the part's length along the axis"},
      {"profile", porosity_profile(lat, final_level, ramp.axis, target, fine_design)},
      {"profile_note", "per slab of the finer cell along the axis: the target and the fraction "
                       "of lattice nodes outside the solid"}};
  nlohmann::json morph = surface_measures(out, lat, d.units);
  t0 = std::chrono::steady_clock::now();
  if (d.morphometry) {
    nlohmann::json cells = nlohmann::json::array();
    for (double size : {ramp.from, ramp.to}) {
      ScaffoldDesign cell = d;
      cell.cell_size = size;
      cell.min_feature = 0.0;
      nlohmann::json c = cell_morphometry(phi, transform, final_level, cell, out.warnings);
      c["cell_size"] = size;
      c["porosity"] = d.porosity;
      cells.push_back(c);
    }
    warn_min_feature(cells, d, out.warnings);
    morph["members"] = cells;
    morph["part"] = part_morphometry(lat, final_level, d);
  }
  r["morphometry"] = morph;
  r["warnings"] = out.warnings;
  r["seconds"]["sample"] = sample_seconds;
  r["seconds"]["morphometry"] = seconds_since(t0);
  return out;
}

nlohmann::json design_cell_morphometry(const Field& phi, const ScaffoldDesign& d) {
  const CellSolid cs = cell_solid(phi, d);
  ScaffoldDesign quiet = d;
  quiet.min_feature = 0.0;
  std::vector<std::string> none;
  return cell_morphometry(cs.distance.n() > 0 ? cs.distance : phi, cs.transform, cs.level, quiet,
                          none);
}

}  // namespace cmcsurf
