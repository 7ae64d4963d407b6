// cmcsurf mesh: a watertight scaffold mesh (surface, network or sheet solid) from a field.
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <stdexcept>

#include "cli_common.h"
#include "commands.h"
#include "io/periodic_mesh_file.h"
#include "measure/sharp_surface.h"
#include "mesh/periodic_surface.h"
#include "mesh_options.h"

namespace cmcsurf::cli {

namespace {

// Some cell on each side of 1/2.
bool has_surface(const Field& phi) {
  bool above = false, below = false;
  for_each_cell(phi.n(), [&](int i, int j, int k) {
    (phi(i, j, k) > 0.5 ? above : below) = true;
  });
  return above && below;
}

struct MeshCommand {
  std::string from;
  MeshOptionStrings mesh;
  bool periodic = false;
  int threads = 0;
  bool quiet = false;
};

// --periodic: the welded mesh of mesh/periodic_surface.h, as JSON (io/periodic_mesh_file.h).
int write_periodic(const MeshCommand& cmd, const CLI::App& app) {
  for (const char* name : {"--tile", "--cell-size", "--units", "--solid", "--other-phase",
                           "--keep-fragments", "--thickness", "--format"})
    if (app.get_option(name)->count() > 0)
      throw UsageError(fmt::format("{}: not with --periodic (the periodic mesh is one computed "
                                   "cell in cell units, the surface only)",
                                   name));
  if (std::filesystem::path(cmd.mesh.out).extension() != ".json")
    throw UsageError(fmt::format("--out: got '{}'; accepted with --periodic: a FILE.json",
                                 cmd.mesh.out));
  refuse_overwriting_inputs(field_inputs(cmd.from, "--from"), cmd.mesh.out);
  const Field phi = load_phi(cmd.from, "--from");
  if (!has_surface(phi))
    throw std::runtime_error(fmt::format(
        "--from '{}': the field has no phi = 1/2 surface (every value on one side of 1/2): "
        "nothing to mesh, nothing written", cmd.from));
  check_field_topology(cmd.from, cmd.mesh.accept_topology_change);
  apply_threads(cmd.threads);
  Field psi = Field::like(phi, 2);
  tanh_profile_inverse(phi, psi);
  const PeriodicSurfaceMesh m = periodic_surface(psi);
  const nlohmann::json stats = periodic_mesh_stats_json(m);
  write_periodic_mesh_json(cmd.mesh.out, m, {{"source", cmd.from}});
  if (!cmd.quiet)
    std::cerr << fmt::format(
        "periodic surface: {} triangles, {} vertices, {} edges, V - E + F = {}, area {:.6g} "
        "(cell units), {} and {}\nwrote {}\n",
        stats["triangles"].get<long>(), stats["vertices"].get<long>(),
        stats["edges"].get<long>(), stats["euler_characteristic"].get<long>(),
        stats["area"].get<double>(), stats["closed"].get<bool>() ? "closed" : "open",
        stats["manifold"].get<bool>() ? "manifold" : "NOT manifold", cmd.mesh.out);
  return 0;
}

}  // namespace

CommandFn add_mesh_command(CLI::App& root) {
  auto cmd = std::make_shared<MeshCommand>();
  CLI::App* app = root.add_subcommand(
      "mesh",
      "Mesh a computed field: the phi = 1/2 surface, the network solid or a sheet solid, tiled, "
      "scaled and capped (STL/PLY/OBJ/3MF, with FILE.json)\nExample: cmcsurf mesh --from "
      "gyroid30 --tile 3x3x3 --cell-size 2.5 --units mm --solid network --out gyroid30.stl");
  app->add_option("--from", cmd->from, "Run directory (with field.vti) or a .vti file")->required();
  add_mesh_output_options(*app, cmd->mesh, true);
  add_threads_option(*app, cmd->threads);
  app->add_flag("--quiet", cmd->quiet, "No summary output");
  app->add_flag("--periodic", cmd->periodic,
                "Write the surface of one cell as a welded periodic mesh (a closed surface on the "
                "torus: each vertex once, triangles with their wrap offsets, per-vertex normals, "
                "H and K) to --out FILE.json; no tiling, scaling or solids");
  return {app, [cmd, app]() -> int {
            if (cmd->periodic) return write_periodic(*cmd, *app);
            refuse_overwriting_inputs(field_inputs(cmd->from, "--from"), cmd->mesh.out);
            const Field phi = load_phi(cmd->from, "--from");
            const MeshPlan plan = finish_mesh_output_options(cmd->mesh, phi.n());
            if (!has_surface(phi))
              throw std::runtime_error(fmt::format(
                  "--from '{}': the field has no phi = 1/2 surface (every value on one side of "
                  "1/2): nothing to mesh, nothing written", cmd->from));
            check_field_topology(cmd->from, cmd->mesh.accept_topology_change);
            apply_threads(cmd->threads);
            const Scaffold s = build_scaffold(phi, plan.params);
            write_mesh_with_report(s.mesh, s.report, plan, {{"source", cmd->from}});
            if (!cmd->quiet) {
              const auto& r = s.report;
              std::cerr << fmt::format(
                  "{} {}: {} triangles, {} vertices, area {:.6g} {}^2{}, Euler characteristic {}, "
                  "{} and {}; meshed in {:.2f} s\nwrote {} and {}.json\n",
                  r["solid"].get<std::string>(), r["tiles"].dump(), r["triangles"].get<long>(),
                  r["vertices"].get<long>(), r["area"].get<double>(), plan.params.units,
                  r.contains("volume") ? fmt::format(", volume {:.6g} {}^3",
                                                     r["volume"].get<double>(), plan.params.units)
                                       : "",
                  r["euler_characteristic"].get<long>(),
                  r["checks"]["closed"].get<bool>() ? "closed" : "open",
                  r["checks"]["manifold"].get<bool>() ? "manifold" : "NOT manifold",
                  r["mesh_seconds"].get<double>(), plan.out.string(), plan.out.string());
              if (r.contains("topology") && r["topology"]["fragments"].get<long>() > 0)
                std::cerr << fmt::format(
                    "{} {} fragments cut off by the box ({:.4g} {}^3){}\n",
                    r["topology"]["fragments_removed"].get<bool>() ? "removed" : "kept",
                    r["topology"]["fragments"].get<long>(),
                    r["topology"]["fragment_volume"].get<double>(), plan.params.units,
                    r["topology"]["fragments_removed"].get<bool>()
                        ? " (--keep-fragments keeps them)"
                        : "");
            }
            return 0;
          }};
}

}  // namespace cmcsurf::cli
