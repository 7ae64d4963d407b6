// cmcsurf graded: a scaffold whose volume fraction ramps along one axis (paper Fig. 2), from
// CMC family members computed by `cmcsurf run` at bracketing volume fractions.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <memory>

#include "common/wall_clock.h"
#include "cli_common.h"
#include "commands.h"
#include "measure/measures.h"
#include "measure/sharp_volume.h"
#include "mesh/graded.h"
#include "mesh_options.h"
#include "run_control.h"

namespace cmcsurf::cli {

namespace {

struct GradedCommand {
  std::vector<std::string> members;
  std::string axis = "z";
  double from_fraction = -1.0, to_fraction = -1.0;
  MeshOptionStrings mesh;
  int threads = 0;
  bool quiet = false;
};

// The --members items, each split at its commas; an empty one is refused by its position.
std::vector<std::string> split_members(const std::vector<std::string>& given) {
  std::vector<std::string> out;
  for (const std::string& g : given) {
    std::size_t pos = 0;
    for (;;) {
      const std::size_t comma = g.find(',', pos);
      const std::string item = g.substr(pos, comma == std::string::npos ? comma : comma - pos);
      if (item.empty())
        throw UsageError(fmt::format("--members: item {} of '{}' is empty; accepted: run "
                                     "directories or .vti files separated by single commas",
                                     out.size() + 1, g));
      out.push_back(item);
      if (comma == std::string::npos) break;
      pos = comma + 1;
    }
  }
  return out;
}

}  // namespace

CommandFn add_graded_command(CLI::App& root) {
  auto cmd = std::make_shared<GradedCommand>();
  CLI::App* app = root.add_subcommand(
      "graded",
      "Graded-porosity scaffold: the volume fraction ramps linearly along an axis across the "
      "tiles, blending the fields of CMC family members (run directories)\nExample: cmcsurf "
      "graded --members g30,g40,g50,g60 --axis z --from-fraction 0.3 --to-fraction 0.6 --tile "
      "2x2x6 --cell-size 2.5 --solid network --out graded.stl");
  app->add_option("--members", cmd->members,
                  "Run directories or .vti files of one surface family (same grid), two or more, "
                  "comma-separated")
      ->required();
  app->add_option("--axis", cmd->axis, "Ramp axis: x, y or z")->capture_default_str();
  app->add_option("--from-fraction", cmd->from_fraction,
                  "Phase-1 volume fraction at the low end of the axis")->required();
  app->add_option("--to-fraction", cmd->to_fraction,
                  "Phase-1 volume fraction at the high end of the axis")->required();
  add_mesh_output_options(*app, cmd->mesh, false);
  add_threads_option(*app, cmd->threads);
  app->add_flag("--quiet", cmd->quiet, "No summary output");
  return {app, [cmd]() -> int {
            GradedRamp ramp;
            if (cmd->axis == "x") ramp.axis = 0;
            else if (cmd->axis == "y") ramp.axis = 1;
            else if (cmd->axis == "z") ramp.axis = 2;
            else throw UsageError(fmt::format("--axis: got '{}'; accepted: x|y|z", cmd->axis));
            ramp.from_fraction = cmd->from_fraction;
            ramp.to_fraction = cmd->to_fraction;
            for (const auto& [name, v] : {std::pair{"--from-fraction", cmd->from_fraction},
                                          std::pair{"--to-fraction", cmd->to_fraction}})
              if (!(v > 0.0 && v < 1.0))
                throw UsageError(fmt::format("{}: got {}; accepted: 0 < value < 1", name, v));
            if (cmd->mesh.solid == "sheet")
              throw UsageError("--solid: graded accepts surface|network");
            cmd->members = split_members(cmd->members);
            if (cmd->members.size() < 2)
              throw UsageError("--members: give at least two run directories");
            std::vector<FileRole> reads;
            for (const std::string& m : cmd->members)
              for (FileRole& f : field_inputs(m, "--members '" + m + "'")) reads.push_back(f);
            refuse_overwriting_inputs(reads, cmd->mesh.out);
            std::vector<GradedMember> members;
            // The volume constraint's tolerance the members were computed to (their
            // report.json; the default for a bare .vti): their targets are accepted as ends.
            double fraction_tol = RunParams{}.volume_tol;
            std::string family, family_member;
            for (const std::string& m : cmd->members) {
              const std::filesystem::path report = std::filesystem::path(m) / "report.json";
              if (std::filesystem::is_regular_file(report)) {
                const nlohmann::json r = read_json_file(report);
                if (r.contains("parameters") && r["parameters"].contains("volume_tol") &&
                    r["parameters"]["volume_tol"].is_number())
                  fraction_tol =
                      std::max(fraction_tol, r["parameters"]["volume_tol"].get<double>());
              }
              GradedMember g;
              std::map<std::string, std::string> metadata;
              g.phi = load_phi(m, "--members", &metadata);
              g.volume_fraction = sharp_volume_fraction(g.phi);
              // One family: every member that names its surface names the same one.
              if (const auto it = metadata.find("surface"); it != metadata.end()) {
                if (family.empty()) family = it->second, family_member = m;
                else if (it->second != family)
                  throw UsageError(fmt::format(
                      "--members: '{}' is a member of surface {}, '{}' of {}; accepted: members "
                      "of one family", m, it->second, family_member, family));
              }
              check_field_topology(m, cmd->mesh.accept_topology_change);
              if (!members.empty() && g.phi.n() != members[0].phi.n())
                throw UsageError(fmt::format("--members: '{}' has grid {}, the first has {}; all "
                                             "members must have the same grid",
                                             m, g.phi.n(), members[0].phi.n()));
              members.push_back(std::move(g));
            }
            std::sort(members.begin(), members.end(), [](const auto& a, const auto& b) {
              return a.volume_fraction < b.volume_fraction;
            });
            for (std::size_t i = 1; i < members.size(); ++i)
              if (members[i].volume_fraction <= members[i - 1].volume_fraction)
                throw UsageError("--members: two members have the same volume fraction");
            const double lo = members.front().volume_fraction, hi = members.back().volume_fraction;
            for (const auto& [name, v] : {std::pair{"--from-fraction", cmd->from_fraction},
                                          std::pair{"--to-fraction", cmd->to_fraction}})
              if (!(v >= lo - fraction_tol && v <= hi + fraction_tol))
                throw UsageError(fmt::format(
                    "{}: got {}; accepted: within the members' volume fractions [{:.6f}, {:.6f}] "
                    "to the volume constraint's tolerance {:g}",
                    name, v, lo, hi, fraction_tol));
            const int n = members[0].phi.n();
            const MeshPlan plan = finish_mesh_output_options(cmd->mesh, n);
            apply_threads(cmd->threads);

            const auto t0 = std::chrono::steady_clock::now();
            const TiledSampler blend =
                graded_sampler(members, ramp, plan.params.tiles, fraction_tol);
            const double sign = plan.params.other_phase ? -1.0 : 1.0;
            const TiledSampler f = [&](int i, int j, int k) {
              return 0.5 + sign * (blend(i, j, k) - 0.5);
            };
            const bool solid = plan.params.solid == SolidKind::kNetwork;
            const TriMesh mesh =
                mesh_tiled(f, n, plan.params.tiles, plan.params.cell_size, 0.5, solid);
            const double seconds =
                seconds_since(t0);
            nlohmann::json report =
                mesh_stats_json(analyze_mesh(mesh), plan.params.tiles, plan.params.units, solid);
            nlohmann::json fractions = nlohmann::json::array();
            for (const auto& m : members) fractions.push_back(m.volume_fraction);
            nlohmann::json extra = {
                {"solid", solid ? "network" : "surface"},
                {"phase", plan.params.other_phase ? "phi < 1/2" : "phi > 1/2"},
                {"tiles", plan.params.tiles},
                {"cell_size", plan.params.cell_size},
                {"units", plan.params.units},
                {"grid", n},
                {"mesh_seconds", seconds},
                {"graded",
                 {{"axis", cmd->axis},
                  {"from_fraction", ramp.from_fraction},
                  {"to_fraction", ramp.to_fraction},
                  {"members", cmd->members},
                  {"member_volume_fractions", fractions},
                  {"fraction_tolerance", fraction_tol},
                  {"blend",
                   "linear in the target fraction between the two bracketing members, per sample"},
                  {"cells_note",
                   "per tile: target at the tile centre, achieved = fraction of phase-1 samples of "
                   "the blended field"},
                  {"cells", graded_cell_report(blend, n, ramp, plan.params.tiles)}}}};
            write_mesh_with_report(mesh, report, plan, extra);
            if (!cmd->quiet)
              std::cerr << fmt::format(
                  "graded {}: {} triangles, {}, meshed in {:.2f} s\nwrote {} and {}.json\n",
                  extra["solid"].get<std::string>(), mesh.triangles.size(),
                  report["checks"]["closed"].get<bool>() ? "closed" : "open", seconds,
                  plan.out.string(), plan.out.string());
            return 0;
          }};
}

}  // namespace cmcsurf::cli
