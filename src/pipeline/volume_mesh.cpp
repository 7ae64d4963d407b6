#include "pipeline/volume_mesh.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "common/wall_clock.h"
#include "io/mesh_output.h"
#include "measure/sharp_volume.h"
#include "model/run_options.h"
#include "properties/voxel_solid.h"

namespace cmcsurf {

VolumeMeshParams volume_mesh_params(const VolumeMeshOptions& o, int n) {
  if (o.solid != "network" && o.solid != "sheet")
    throw OptionError(fmt::format("--solid: got '{}'; accepted: network|sheet", o.solid));
  const bool sheet = o.solid == "sheet";
  const bool has_porosity = std::isfinite(o.porosity);
  if (has_porosity && !sheet)
    throw OptionError("--porosity: only with --solid sheet (a network's porosity is the field's)");
  if (has_porosity && o.thickness != 0.0)
    throw OptionError("--porosity: give --porosity or --thickness, not both");
  if (has_porosity && !(o.porosity > 0.0 && o.porosity < 1.0))
    throw OptionError(fmt::format("--porosity: got {}; accepted: 0 < P < 1", o.porosity));
  if (sheet && !has_porosity && o.thickness == 0.0)
    throw OptionError("--thickness: --solid sheet needs --thickness T or --porosity P");
  // Tiles, cell size, units and the thickness's range as `cmcsurf mesh` checks them.
  MeshOutputOptions m;
  m.tile = o.tile;
  m.cell_size = o.cell_size;
  m.units = o.units;
  m.solid = has_porosity ? "network" : o.solid;  // no thickness to check yet
  m.thickness = has_porosity ? 0.0 : o.thickness;
  const ScaffoldParams s = scaffold_params(m, n);
  VolumeMeshParams p;
  p.solid = sheet ? SolidKind::kSheet : SolidKind::kNetwork;
  p.porosity = o.porosity;
  p.thickness = sheet && !has_porosity ? o.thickness / o.cell_size : 0.0;
  p.tiles = s.tiles;
  for (int c = 0; c < 3; ++c)
    if (p.tiles[c] > kMaxVolumeMeshTiles)
      throw OptionError(fmt::format("--tile: got '{}'; accepted for volume meshes: 1..{} per "
                                    "axis (each tile copies the cell's tets)",
                                    o.tile, kMaxVolumeMeshTiles));
  p.cell_size = s.cell_size;
  p.units = s.units;
  if (o.cut != "flat" && o.cut != "fundamental")
    throw OptionError(fmt::format("--cut: got '{}'; accepted: flat|fundamental", o.cut));
  p.flat_faces = o.cut == "flat";
  // Sizes: output units in, unit cells inside. Below a tenth of a grid spacing the mesh
  // resolves nothing the field has; above a quarter cell it no longer holds the solid's arms.
  const double L = o.cell_size, lo = 0.1 * L / n, hi = 0.25 * L;
  auto check_size = [&](const char* name, double v) {
    if (!(v >= lo && v <= hi))
      throw OptionError(fmt::format("--{}: got {}; accepted: {:.6g} .. {:.6g} {} (a tenth of "
                                    "the N = {} grid spacing to a quarter of the cell)",
                                    name, v, lo, hi, o.units, n));
  };
  auto given = [](double v) { return !std::isnan(v); };
  if (given(o.size) && (given(o.size_max) || given(o.size_min)))
    throw OptionError("--size: give --size or --size-min/--size-max, not both");
  if (given(o.size)) check_size("size", o.size), p.size_max = o.size / L;
  if (given(o.size_max)) check_size("size-max", o.size_max), p.size_max = o.size_max / L;
  if (given(o.size_min)) {
    check_size("size-min", o.size_min);
    p.size_min = o.size_min / L;
    if (!(p.size_min < p.size_max))
      throw OptionError(fmt::format("--size-min: got {}; accepted: below the longest edge {} {}",
                                    o.size_min, p.size_max * L, o.units));
  }
  p.facet_distance = p.size_max * kDefaultFacetDistanceShare;
  if (given(o.facet_distance)) {
    const double flo = 1e-4 * L, fhi = p.size_max * L;
    if (!(o.facet_distance >= flo && o.facet_distance <= fhi))
      throw OptionError(fmt::format("--facet-distance: got {}; accepted: {:.6g} .. {:.6g} {} "
                                    "(1e-4 cell to the longest edge)",
                                    o.facet_distance, flo, fhi, o.units));
    p.facet_distance = o.facet_distance / L;
  }
  return p;
}

SolidLevelSet solid_level_set(const Field& phi, SolidKind solid, double thickness) {
  SolidLevelSet s;
  if (solid == SolidKind::kNetwork) {
    s.g = Field::like(phi, 1);
    curvature_corrected(phi, s.g);  // as cmc_voxel_solid: the run's sharp volume fraction
    s.level = 0.5;
    return s;
  }
  const Field d = signed_distance(phi, 0.5 * thickness + 3.0 * phi.h());
  s.g = Field::like(d, 1);
  for_each_cell(d, [&](int i, int j, int k) { s.g(i, j, k) = -std::abs(d(i, j, k)); });
  s.g.exchange_halo();
  s.level = -0.5 * thickness;
  return s;
}

double solid_fraction_above(const Field& g, double level) {
  Field fraction(g.n(), 0);
  dual_cell_fractions(g, level, fraction);
  double sum = 0.0;
  for_each_cell(fraction, [&](int i, int j, int k) { sum += fraction(i, j, k); });
  return sum / fraction.global_cells();
}

SheetForPorosity sheet_for_porosity(const Field& phi, double porosity) {
  if (!(porosity > 0.0 && porosity < 1.0))
    throw std::invalid_argument(fmt::format("--porosity: got {}; accepted: 0 < P < 1", porosity));
  const double target = 1.0 - porosity, h = phi.h();
  // A thin wall of thickness T around a surface of area A per cell holds T A: the band starts
  // at 1.5x the half thickness that suggests, and grows when the wall turns out thicker.
  const double area = analyze_mesh(periodic_surface_mesh(phi)).area;
  SheetForPorosity s;
  s.band = std::min(0.5, 0.75 * target / std::max(area, 1e-12) + 3.0 * h);
  for (;;) {
    const Field d = signed_distance(phi, s.band);
    ++s.distance_fields;
    s.level_set.g = Field::like(d, 1);
    Field& g = s.level_set.g;
    for_each_cell(d, [&](int i, int j, int k) { g(i, j, k) = -std::abs(d(i, j, k)); });
    g.exchange_halo();
    auto f = [&](double t) {
      ++s.evaluations;
      return solid_fraction_above(g, -0.5 * t) - target;
    };
    // Illinois (regula falsi that halves the stale end's value): the solid fraction is a
    // smooth increasing function of T, so a handful of evaluations reach the tolerance that
    // bisection needs ~25 for. Beyond 2 x band every value is clamped: the bracket ends there.
    double lo = 0.0, hi = 2.0 * s.band + 2.0 * h;
    double flo = -target, fhi = f(hi);
    double t = hi, ft = fhi;
    int stale = 0;
    for (int it = 0; it < 100 && std::abs(ft) > kSheetPorosityTol && hi - lo > 1e-14; ++it) {
      t = (lo * fhi - hi * flo) / (fhi - flo);
      if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
      ft = f(t);
      if (ft < 0) {
        lo = t, flo = ft;
        if (stale == -1) fhi *= 0.5;
        stale = -1;
      } else {
        hi = t, fhi = ft;
        if (stale == 1) flo *= 0.5;
        stale = 1;
      }
    }
    s.thickness = t;
    s.solid_fraction = ft + target;
    // Exact while every Kuhn tet the level crosses has its corners inside the band.
    if (0.5 * t + 3.0 * h <= s.band || s.band >= 0.5) break;
    s.band = std::min(0.5, 0.75 * t + 3.0 * h);
  }
  s.level_set.level = -0.5 * s.thickness;
  return s;
}

VolumeMesh build_volume_mesh(const Field& phi, const VolumeMeshParams& p) {
  if (!periodic_mesher_available())
    throw std::runtime_error(
        "volume-mesh: this cmcsurf was built without CGAL (Debian libcgal-dev libgmp-dev "
        "libmpfr-dev); install them and reconfigure (scripts/setup.sh)");
  VolumeMesh out;
  const auto t0 = WallClock::now();
  // The solid as properties/voxel_solid.h sees it: its volume is the reference. A sheet of
  // given thickness takes its voxel fractions from the level set below (the same distance
  // field, computed once: it is the slow part at 64^3).
  const bool sheet_of_thickness = p.solid == SolidKind::kSheet && std::isnan(p.porosity);
  out.thickness = p.thickness;
  SolidLevelSet ls;
  nlohmann::json thickness_solve;
  if (p.solid == SolidKind::kNetwork) {
    out.solid_fraction = cmc_voxel_solid(phi, {}).solid_fraction;
    ls = solid_level_set(phi, p.solid, 0.0);
  } else if (sheet_of_thickness) {
    ls = solid_level_set(phi, p.solid, out.thickness);
    out.solid_fraction = solid_fraction_above(ls.g, ls.level);
  } else {
    SheetForPorosity s = sheet_for_porosity(phi, p.porosity);
    ls = std::move(s.level_set);
    out.thickness = s.thickness;
    out.solid_fraction = s.solid_fraction;
    thickness_solve = {{"band", s.band},
                       {"distance_fields", s.distance_fields},
                       {"evaluations", s.evaluations},
                       {"porosity_error", 1.0 - s.solid_fraction - p.porosity}};
  }
  const double level_set_seconds = seconds_since(t0);

  // CGAL's cell_size bounds the circumradius: an edge, a chord of the circumsphere, is at most
  // twice that. facet_size bounds the surface Delaunay balls the same way.
  PeriodicMeshCriteria c;
  c.cell_radius = 0.5 * p.size_max;
  c.facet_size = 0.5 * p.size_max;
  c.facet_distance = p.facet_distance;
  const auto t1 = WallClock::now();
  PeriodicTets torus = mesh_periodic_solid(ls.g, ls.level, c);
  const double mesh_seconds = seconds_since(t1);
  const std::size_t torus_vertices = torus.vertices.size(), torus_tets = torus.tets.size();
  const auto t2 = WallClock::now();
  CellFaceCut cut;
  if (p.flat_faces) cut = cut_at_cell_faces(torus, p.cut_snap);
  const double cut_seconds = seconds_since(t2);
  // The sizes asked for: short edges collapsed, long ones split (on the torus, so both faces
  // of the box change alike); then the smoothing, which keeps edges within them.
  const auto t6 = WallClock::now();
  EdgeSizing sizing;
  if (p.flat_faces) sizing = enforce_edge_sizes(torus, {p.size_min, p.size_max, p.facet_distance});
  const double size_seconds = seconds_since(t6);
  const auto t5 = WallClock::now();
  SliverSmoothing smoothing;
  const bool smooth = p.flat_faces && p.sliver_target_deg > 0.0;
  if (smooth)
    smoothing =
        smooth_slivers(torus, p.sliver_target_deg, kSliverSweeps, p.size_max, p.size_min);
  // Last, so that nothing puts a vertex back on a face: one-sided face vertices off it.
  OneSidedFaceVertices lifted;
  if (p.flat_faces)
    lifted = lift_one_sided_face_vertices(torus, kOneSidedLiftFacetShare * p.facet_distance,
                                          p.size_min, p.size_max);
  const double smooth_seconds = seconds_since(t5);
  const auto t4 = WallClock::now();
  out.mesh = unfold_periodic_tets(torus, p.tiles, p.cell_size);
  const double unfold_seconds = seconds_since(t4);
  const auto t3 = WallClock::now();
  const double L = p.cell_size;
  const TetMeshStats s = analyze_tet_mesh(out.mesh, p.size_min * L, p.size_max * L);
  const double analyze_seconds = seconds_since(t3);

  nlohmann::json& r = out.report;
  r = tet_mesh_stats_json(s, p.units);
  const int cells = p.tiles[0] * p.tiles[1] * p.tiles[2];
  const double volume_field = out.solid_fraction * cells * L * L * L;
  r["solid"] = solid_kind_name(p.solid);
  r["tiles"] = p.tiles;
  r["cell_size"] = L;
  r["units"] = p.units;
  r["grid"] = phi.n();
  r["volume_field"] = volume_field;
  r["volume_relative_error"] = (s.volume - volume_field) / volume_field;
  r["porosity_field"] = 1.0 - out.solid_fraction;
  if (p.solid == SolidKind::kSheet)
    r["thickness"] = out.thickness * L;
  if (!thickness_solve.is_null()) r["thickness_solve"] = thickness_solve;
  r["domain"] = p.flat_faces
                    ? "the box [0, period] cut flat: the periodic mesh split at the cell faces; "
                      "opposite faces carry the same triangulation, node for node (pairing)"
                    : "a fundamental domain of the periodic solid: each tet where its centroid "
                      "falls in the box; the cut faces come in pairs one period apart (pairing)";
  if (p.flat_faces)
    r["cut"] = {{"faces", "flat"},
                {"snap_share_of_shortest_edge", p.cut_snap},
                {"snapped_vertices", cut.snapped},
                {"pushed_vertices", cut.pushed},
                {"snaps_refused", cut.snaps_refused},
                {"max_snap", cut.max_snap * L},
                {"split_tets", cut.split_tets},
                {"added_vertices", cut.cut_vertices},
                {"degenerate_pieces", cut.degenerate},
                {"one_sided_face_vertices", lifted.found},
                {"lifted_vertices", lifted.lifted},
                {"split_face_vertices", lifted.split},
                {"max_lift", lifted.max_lift * L},
                {"l_vertices_moved_into_cell", lifted.moved_into_cell},
                {"recut_tets", lifted.recut_tets},
                {"max_cell_move", lifted.max_cell_move * L},
                {"moved_below_floor", lifted.moved_below_floor},
                {"pairing_floor_deg", kPairingFloorDeg},
                {"min_dihedral_below_floor_deg",
                 lifted.moved_below_floor ? nlohmann::json(lifted.min_dihedral_below_floor)
                                          : nlohmann::json(nullptr)},
                {"face_vertices_left_unpaired", lifted.left},
                {"units", p.units}};
  else
    r["cut"] = {{"faces", "fundamental domain"}};
  if (smooth) {
    const auto hist = dihedral_histogram_json;
    r["smoothing"] = {{"target_min_dihedral_deg", p.sliver_target_deg},
                      {"min_dihedral_before_deg", smoothing.min_dihedral_before},
                      {"min_dihedral_after_deg", smoothing.min_dihedral_after},
                      {"tets_below_target_before", smoothing.tets_below_target_before},
                      {"tets_below_target_after", smoothing.tets_below_target_after},
                      {"min_dihedral_histogram_before", hist(smoothing.histogram_before)},
                      {"min_dihedral_histogram_after", hist(smoothing.histogram_after)},
                      {"vertices_tried", smoothing.vertices_tried},
                      {"moves", smoothing.moves},
                      {"sweeps", smoothing.sweeps},
                      {"fixed_vertices", smoothing.fixed_vertices},
                      {"peeled_surface_slivers", smoothing.peeled},
                      {"peeled_volume", smoothing.peeled_volume * L * L * L},
                      {"note", "per cell (the torus mesh after the cut); surface vertices fixed"}};
  }
  if (p.flat_faces)
    r["sizing"] = {{"size_min", p.size_min * L},
                   {"size_max", p.size_max * L},
                   {"below_size_min_before", sizing.below_min_before},
                   {"below_size_min_after", sizing.below_min_after},
                   {"above_size_max_before", sizing.above_max_before},
                   {"above_size_max_after", sizing.above_max_after},
                   {"collapsed_edges", sizing.collapsed},
                   {"split_edges", sizing.split},
                   {"collapses_refused",
                    {{"fixed_vertex", sizing.refused_fixed},
                     {"topology", sizing.refused_topology},
                     {"quality", sizing.refused_quality},
                     {"length", sizing.refused_length},
                     {"surface_distance", sizing.refused_surface}}},
                   {"splits_refused", sizing.split_refused},
                   {"units", p.units},
                   {"note", "per cell (the torus mesh after the cut, before the smoothing); "
                            "edge_length counts the block's edges after it"}};
  r["criteria"] = {{"size_max", p.size_max * L},
                   {"size_min", p.size_min * L},
                   {"facet_distance", p.facet_distance * L},
                   {"cell_circumradius_max", c.cell_radius * L},
                   {"facet_size", c.facet_size * L},
                   {"facet_angle_deg", c.facet_angle},
                   {"cell_radius_edge_ratio", c.radius_edge},
                   {"perturb_sliver_bound_deg", c.perturb_bound_deg},
                   {"exude_sliver_bound_deg", c.exude_bound_deg},
                   {"repeatable", c.repeatable},
                   {"units", p.units},
                   {"size_min_note",
                    p.flat_faces ? "CGAL 5.5 has no lower size bound: edges below it are "
                                   "collapsed after the cut where the surface, the faces and "
                                   "the quality allow (sizing); edge_length.size_min_met says "
                                   "whether the mesh meets it"
                                 : "not enforced with --cut fundamental (CGAL's tets "
                                   "untouched); edge_length.size_min_met says whether the "
                                   "mesh meets it"}};
  r["torus"] = {{"vertices", torus_vertices}, {"tets", torus_tets},
                {"vertices_split", torus.vertices.size()}, {"tets_split", torus.tets.size()}};
  // The pairs by translation, in block periods.
  std::map<std::array<long, 3>, std::size_t> classes;
  for (const auto& pr : out.mesh.pairs) {
    std::array<long, 3> k;
    for (int a = 0; a < 3; ++a) k[a] = std::lround(pr.translation[a] / out.mesh.period[a]);
    ++classes[k];
  }
  nlohmann::json translations = nlohmann::json::array();
  for (const auto& [k, count] : classes)
    translations.push_back({{"periods", k},
                            {"translation", {k[0] * out.mesh.period[0], k[1] * out.mesh.period[1],
                                             k[2] * out.mesh.period[2]}},
                            {"pairs", count}});
  r["pairing"] = {{"pairs", out.mesh.pairs.size()},
                  {"period", out.mesh.period},
                  {"translations", translations},
                  {"max_mismatch", s.pair_mismatch},
                  {"max_mismatch_note", "|x_slave - x_master - translation| / largest period"}};
  r["mesher"] = periodic_mesher_name();
  r["seconds"] = {{"level_set", level_set_seconds},
                  {"mesh", mesh_seconds},
                  {"cut", cut_seconds},
                  {"size", size_seconds},
                  {"smooth", smooth_seconds},
                  {"unfold", unfold_seconds},
                  {"analyze", analyze_seconds}};
  r["mesh_seconds"] = mesh_seconds;
  return out;
}

}  // namespace cmcsurf
