// cmcsurf volume-mesh: a periodic tetrahedral mesh of the network or sheet solid for a user's
// finite-element code (MSH/INP/VTU/XDMF with the periodic node pairs, and FILE.json).
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <stdexcept>

#include "cli_common.h"
#include "commands.h"
#include "io/tet_mesh_writers.h"
#include "pipeline/volume_mesh.h"
#include "mesh_options.h"

namespace cmcsurf::cli {

namespace {

struct VolumeMeshCommand {
  std::string from;
  VolumeMeshOptions options;
  std::string format;
  std::string out;
  int threads = 0;
  bool quiet = false;
};

}  // namespace

CommandFn add_volume_mesh_command(CLI::App& root) {
  auto cmd = std::make_shared<VolumeMeshCommand>();
  VolumeMeshOptions& o = cmd->options;
  CLI::App* app = root.add_subcommand(
      "volume-mesh",
      "Periodic tetrahedral mesh of the network or sheet solid for finite-element codes: "
      "opposite boundary nodes paired (MSH 4.1 $Periodic, Abaqus .inp node sets, VTU, XDMF), "
      "with FILE.json\nExample: cmcsurf volume-mesh --from gyroid30 --solid network "
      "--cell-size 2.5 --units mm --out gyroid30.msh");
  app->add_option("--from", cmd->from, "Run directory (with field.vti) or a .vti file")->required();
  app->add_option("--solid", o.solid, "network (phi > 1/2) or sheet (a wall around phi = 1/2)")
      ->capture_default_str();
  app->add_option("--porosity", o.porosity, "Sheet: the wall thickness that leaves porosity P");
  app->add_option("--thickness", o.thickness, "Sheet: wall thickness in output units");
  app->add_option("--tile", o.tile, "Unit cells along x, y, z: AxBxC (or A), up to 8 each")
      ->capture_default_str();
  app->add_option("--cell-size", o.cell_size, "Edge of one unit cell in output units")
      ->capture_default_str();
  app->add_option("--units", o.units, "Length unit of the coordinates")->capture_default_str();
  app->add_option("--size", o.size,
                  fmt::format("Longest edge, output units (default {} cell)",
                              kDefaultVolumeMeshSize));
  app->add_option("--size-max", o.size_max, "Longest edge, output units (as --size)");
  app->add_option("--size-min", o.size_min,
                  "Shortest edge, output units: shorter edges are collapsed after the flat cut "
                  "where the surface (within --facet-distance), the faces and the quality allow; "
                  "FILE.json says whether the mesh meets it (edge_length.size_min_met) and counts "
                  "the edges left below it");
  app->add_option("--facet-distance", o.facet_distance,
                  fmt::format("Surface facets within this of phi = 1/2, output units (default "
                              "{:g} of the longest edge)", kDefaultFacetDistanceShare));
  app->add_option("--cut", o.cut,
                  "flat: the box cut by its planes, opposite faces mirror images; fundamental: "
                  "whole tets, jagged cut faces (CGAL's angles, fewer tets)")
      ->capture_default_str();
  app->add_option("--format", cmd->format,
                  std::string("Mesh format: ") + tet_mesh_format_list() + " (default: from --out)");
  app->add_option("--out", cmd->out, "Output mesh file (a report goes to FILE.json)")->required();
  add_threads_option(*app, cmd->threads);
  app->add_flag("--quiet", cmd->quiet, "No summary output");
  return {app, [cmd]() -> int {
            refuse_overwriting_inputs(field_inputs(cmd->from, "--from"), cmd->out);
            TetMeshFormat format;
            try {
              format = tet_mesh_format(cmd->format, cmd->out);
            } catch (const std::invalid_argument& e) {
              throw UsageError(fmt::format("--format: {} (or give --out a .msh/.inp/.vtu/.xdmf "
                                           "name)", e.what()));
            }
            if (std::filesystem::is_directory(cmd->out))
              throw UsageError(fmt::format("--out: '{}' is a directory; give a file name",
                                           cmd->out));
            const Field phi = load_phi(cmd->from, "--from");
            VolumeMeshParams p;
            try {
              p = volume_mesh_params(cmd->options, phi.n());
            } catch (const OptionError& e) {
              throw UsageError(e.what());
            }
            apply_threads(cmd->threads);
            const VolumeMesh vm = build_volume_mesh(phi, p);
            nlohmann::json report = vm.report;
            report["source"] = cmd->from;
            write_tet_mesh_with_report(
                vm.mesh, format, cmd->out,
                fmt::format("cmcsurf volume-mesh: {} solid of {}, tiles {}, units {}",
                            solid_kind_name(p.solid), cmd->from, report["tiles"].dump(), p.units),
                report);
            if (!cmd->quiet) {
              const auto& r = report;
              std::cerr << fmt::format(
                  "{} {}: {} tets, {} nodes, volume {:.6g} {}^3 (field {:.6g}, {:+.3f} %), min "
                  "dihedral {:.1f} deg, {} periodic pairs (mismatch {:.1e}); meshed in {:.2f} s"
                  "\nwrote {} and {}.json\n",
                  r["solid"].get<std::string>(), r["tiles"].dump(), r["tets"].get<long>(),
                  r["nodes"].get<long>(), r["volume"].get<double>(), p.units,
                  r["volume_field"].get<double>(),
                  100 * r["volume_relative_error"].get<double>(),
                  r["quality"]["min_dihedral_deg"].get<double>(),
                  r["pairing"]["pairs"].get<long>(), r["pairing"]["max_mismatch"].get<double>(),
                  r["mesh_seconds"].get<double>(), cmd->out, cmd->out);
              const auto& e = r["edge_length"];
              if (e["below_size_min"].get<long>() > 0)
                std::cerr << fmt::format(
                    "note: {} of {} edges are shorter than --size-min ({} on the surface, {} on "
                    "the cut faces, {} with an end on a box edge, where the surface or the cut "
                    "crosses it; the shortest {:.3g} {}): their collapse would have moved the "
                    "surface or a face or spoilt a tet; the mesh is kept, FILE.json counts "
                    "them (edge_length.size_min_met false, sizing.collapses_refused)\n",
                    e["below_size_min"].get<long>(), r["edges"].get<long>(),
                    e["below_size_min_on_surface"].get<long>(),
                    e["below_size_min_on_cut"].get<long>(),
                    e["below_size_min_at_box_edges"].get<long>(), e["min"].get<double>(),
                    p.units);
              if (e["above_size_max"].get<long>() > 0)
                std::cerr << fmt::format(
                    "note: {} of {} edges are longer than --size (the longest {:.3g} {}): their "
                    "split would have left an edge under --size-min or a tet under {} degrees; "
                    "FILE.json counts them "
                    "(edge_length.above_size_max, sizing.splits_refused)\n",
                    e["above_size_max"].get<long>(), r["edges"].get<long>(),
                    e["max"].get<double>(), p.units, kSizingFloorDeg);
              if (r["checks"]["unpaired_plane_nodes"].get<long>() > 0)
                std::cerr << fmt::format(
                    "note: {} nodes on the box's planes have no partner one period away: a box "
                    "edge or corner vertex that no move off its faces kept above {} degrees "
                    "(cut.face_vertices_left_unpaired); pairs by $Periodic or node sets are "
                    "complete, ties by coordinates miss them\n",
                    r["checks"]["unpaired_plane_nodes"].get<long>(), kPairingFloorDeg);
            }
            return 0;
          }};
}

}  // namespace cmcsurf::cli
