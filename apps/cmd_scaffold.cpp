// cmcsurf scaffold: design targets in (surface, porosity, solid, cell size, box), a clean
// printable part out (docs/scaffolds.md). The options and the driver are the library's
// (driver/scaffold_run.h, shared with Python's cmcsurf.scaffold): this file adds them to the
// command line and prints the summary.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <tuple>

#include "common/wall_clock.h"
#include "cli_common.h"
#include "commands.h"
#include "driver/scaffold_run.h"
#include "model/run_options.h"

namespace cmcsurf::cli {

namespace {

struct ScaffoldCommand {
  ScaffoldOptions options;
  RunParams params;
  RunOptionStrings strings;
  std::vector<std::pair<std::string, const CLI::Option*>> given;  // table key, its option
  int threads = 0;
  bool quiet = false;
};

// One line every few seconds while a large part is decimated: the triangles left and, with a
// budget, the share of its collapses done (with a tolerance alone their number is not known
// beforehand: the share of the input's triangles removed).
DecimateProgress decimate_progress(const ScaffoldCommand& cmd) {
  if (cmd.quiet) return {};
  auto last = std::make_shared<double>(-1.0);
  auto before = std::make_shared<std::size_t>(0);
  auto t0 = std::make_shared<std::chrono::steady_clock::time_point>(
      std::chrono::steady_clock::now());
  const std::size_t budget = std::size_t(std::max(0L, cmd.options.max_triangles));
  return [last, before, t0, budget](DecimateStage stage, int attempt, std::size_t triangles) {
    const double now = seconds_since(*t0);
    if (stage == DecimateStage::kCollapse && attempt > 0) *before = triangles;
    if (attempt == 0 && now - *last < 2.0) return;
    *last = now;
    if (stage == DecimateStage::kCollapse && attempt > 0) {
      std::cerr << fmt::format("decimating {} triangles (attempt {}, {:.0f} s)\n", triangles,
                               attempt, now);
    } else if (stage == DecimateStage::kCollapse) {
      const double removed = double(*before) - double(std::min(triangles, *before));
      const std::string share =
          budget > 0 && budget < *before
              ? fmt::format("{:.0f} % of the collapses to {}", 100.0 * removed /
                                                                   double(*before - budget),
                            budget)
              : fmt::format("{:.0f} % of the triangles removed",
                            100.0 * removed / double(std::max<std::size_t>(*before, 1)));
      std::cerr << fmt::format("  {} triangles left, {} ({:.0f} s)\n", triangles, share, now);
    } else {
      std::cerr << fmt::format("  measuring the distance of the {} triangles to the part "
                               "({:.0f} s)\n", triangles, now);
    }
  };
}

// How a ramp runs: "along z", or "from the surface to 2 mm deep".
std::string ramp_words(const nlohmann::json& graded) {
  if (graded.value("by", "axis") == "surface")
    return fmt::format("from the surface to {:g} {} deep", graded["depth"].get<double>(),
                       graded["units"].get<std::string>());
  return "along " + graded["axis"].get<std::string>();
}

// What a design solved and from which target, and each target recomputed on the part.
void print_design(const nlohmann::json& design, const std::string& units) {
  auto solved = [&](const nlohmann::json& rep) {
    std::string text;
    const auto& s = rep["solved"];
    if (s.contains("porosity"))
      text += fmt::format(" porosity {:.4f} ({})", s["porosity"].get<double>(),
                          rep["solved_by"]["porosity"].get<std::string>());
    if (s.contains("cell_size"))
      text += fmt::format(" cell size {:.4g} {} ({})", s["cell_size"].get<double>(), units,
                          rep["solved_by"]["cell_size"].get<std::string>());
    const std::size_t count = rep["evaluations"].size();
    return text + fmt::format(" from {} evaluation{}", count, count == 1 ? "" : "s");
  };
  std::string line = "design:";
  if (design.contains("ends"))
    line += " graded," + solved(design["ends"][0]) + "; to" + solved(design["ends"][1]);
  else if (design.contains("solved"))
    line += solved(design);
  if (design.contains("seconds"))
    line += fmt::format(" ({:.1f} s)", design["seconds"].get<double>());
  const auto& a = design["achieved"];
  for (const auto& [key, name, unit] :
       {std::tuple{"modulus_gpa", "modulus", std::string("GPa")},
        {"permeability_m2", "permeability", std::string("m^2")},
        {"pore_size", "mean pore size", units}})
    if (a.contains(key))
      line += fmt::format("; {} {:.4g} {} (target {:.4g}, {:+.1f} %)", name,
                          a[key]["value"].get<double>(), unit, a[key]["target"].get<double>(),
                          100.0 * a[key]["relative_error"].get<double>());
  if (a.contains("min_wall"))
    line += fmt::format("; thinnest wall (5th percentile) {:.4g} {} ({} --min-wall {})",
                        a["min_wall"]["wall_p5"].get<double>(), units,
                        a["min_wall"]["met"].get<bool>() ? "meets" : "BELOW",
                        a["min_wall"]["min_wall"].get<double>());
  std::cerr << line << "\n";
}

// The summary of FILE.json as written: the part, its morphometry, the comparison, the design.
void print_summary(const ScaffoldCommand& cmd, const ScaffoldRun& run) {
  const ScaffoldOptions& o = cmd.options;
  const nlohmann::json& r = run.report;
  const nlohmann::json& design = r["design"];
  const std::string units = design["units"].get<std::string>();
  std::vector<double> size(3);  // the box, or the shape's bounding box (design.size null)
  for (int c = 0; c < 3; ++c)
    size[c] = design["size"].is_array()
                  ? design["size"][c].get<double>()
                  : r["shape"]["bounding_box"]["max"][c].get<double>() -
                        r["shape"]["bounding_box"]["min"][c].get<double>();
  const bool sheet = design["solid"].get<std::string>() == "sheet";
  const double from = r.contains("graded") ? r["graded"]["porosity_from"].get<double>() : NAN,
               to = r.contains("graded") ? r["graded"]["porosity_to"].get<double>() : NAN;
  const auto& m = r["morphometry"];
  const auto& t = r["topology"];
  std::cerr << fmt::format(
      "{} {} scaffold, {}x{}x{} {}: porosity {:.4f} (target {}, error {:+.1e}){}\n"
      "{} triangles, {}, {}; {} fragments removed ({:.3g} {}^3); pores percolate x y z\n",
      o.surface, o.solid, size[0], size[1], size[2], units,
      r["porosity"].get<double>(),
      r.contains("graded")
          ? fmt::format("{:.6g}:{:.6g} {}, mean {:.6g}", from, to, ramp_words(r["graded"]),
                        r["graded"].value("porosity_mean", 0.5 * (from + to)))
          : fmt::format("{:.6g}", design["porosity"].get<double>()),
      r["porosity_error"].get<double>(),
      sheet ? fmt::format(", wall thickness {:.4g} {}", r["sheet"]["thickness"].get<double>(),
                          units)
            : "",
      r["triangles"].get<long>(), r["checks"]["closed"].get<bool>() ? "closed" : "OPEN",
      r["checks"]["manifold"].get<bool>() ? "manifold" : "NOT manifold",
      t["fragments_removed"].get<bool>() ? t["fragments"].get<long>() : 0,
      t["fragments_removed"].get<bool>() ? t["fragment_volume"].get<double>() : 0.0, units);
  if (m.contains("wall_thickness") && m.contains("pore_size"))
    std::cerr << fmt::format(
        "specific surface {:.4g} 1/{}; wall thickness mean {:.4g} min {:.4g} {}; pore size mean "
        "{:.4g} min {:.4g} {}\n",
        m["specific_surface"].get<double>(), units, m["wall_thickness"]["mean"].get<double>(),
        m["wall_thickness"]["min"].get<double>(), units, m["pore_size"]["mean"].get<double>(),
        m["pore_size"]["min"].get<double>(), units);
  if (m.contains("part") && m["part"].value("measured", false)) {
    const auto& p = m["part"];
    std::cerr << fmt::format(
        "the part as trimmed ({:.3g} {} voxels): wall p5 {:.4g} median {:.4g} min {:.4g} {}; "
        "pore p5 {:.4g} median {:.4g} {}{}\n",
        p["voxel"].get<double>(), units, p["wall_thickness"]["p5"].get<double>(),
        p["wall_thickness"]["p50"].get<double>(), p["wall_thickness"]["min"].get<double>(),
        units, p["pore_size"]["p5"].get<double>(), p["pore_size"]["p50"].get<double>(), units,
        p.contains("throat")
            ? fmt::format("; throat {:.4g} {}", p["throat"]["min"].get<double>(), units)
            : "");
  }
  if (m.contains("members")) {
    // A ramp: each member's cell, from the most porous to the densest.
    std::string line = fmt::format("specific surface {:.4g} 1/{}; wall thickness and pore size "
                                   "mean (min) per member, {}:",
                                   m["specific_surface"].get<double>(), units, units);
    for (auto it = m["members"].begin(); it != m["members"].end(); ++it)
      line += fmt::format("{} {}: wall {:.3g} ({:.3g}), pore {:.3g} ({:.3g})",
                          it == m["members"].begin() ? "" : ";",
                          it->contains("cell_size")  // a graded cell size: one per cell size
                              ? fmt::format("cell {:g}", (*it)["cell_size"].get<double>())
                              : fmt::format("porosity {:.2f}", (*it)["porosity"].get<double>()),
                          (*it)["wall_thickness"]["mean"].get<double>(),
                          (*it)["wall_thickness"]["min"].get<double>(),
                          (*it)["pore_size"]["mean"].get<double>(),
                          (*it)["pore_size"]["min"].get<double>());
    std::cerr << line << "\n";
  }
  // A band without lattice nodes has null numbers in FILE.json (NaN written): "nan" here.
  auto band = [](const nlohmann::json& b, const char* key) {
    return b[key].is_number() ? b[key].get<double>() : NAN;
  };
  if (r.contains("graded") && r["graded"].value("by", "axis") == "surface") {
    std::string line = fmt::format("porosity by depth ({}), target | measured:", units);
    for (const auto& b : r["graded"]["profile"]) {
      const std::string to =
          b["depth_to"].is_null() ? "core" : fmt::format("{:g}", b["depth_to"].get<double>());
      line += fmt::format(" {:g}-{}: {:.3f} | {:.3f};", b["depth_from"].get<double>(), to,
                          band(b, "porosity_target"), band(b, "porosity_nodes"));
    }
    line.pop_back();
    std::cerr << line << "\n";
  } else if (r.contains("graded") || r.contains("graded_cell_size")) {
    const nlohmann::json& g = r.contains("graded") ? r["graded"] : r["graded_cell_size"];
    std::string line = "porosity per cell along " + g["axis"].get<std::string>() +
                       ", target | measured:";
    for (const auto& b : g["profile"])
      line += fmt::format(" {:.3f} | {:.3f};", band(b, "porosity_target"),
                          band(b, "porosity_nodes"));
    line.pop_back();
    std::cerr << line << "\n";
  }
  if (r.contains("compare_nodal") && r["compare_nodal"]["nodal"].contains("error")) {
    std::cerr << "--compare-nodal: the nodal twin is not a valid part: "
              << r["compare_nodal"]["nodal"]["error"].get<std::string>() << "\n";
  } else if (r.contains("compare_nodal")) {
    const auto& c = r["compare_nodal"];
    std::cerr << fmt::format("{:<28} {:>12} {:>12}\n", "--compare-nodal", "CMC", "nodal");
    auto row = [&](const std::string& name, const nlohmann::json& a, const nlohmann::json& b) {
      std::cerr << fmt::format("{:<28} {:>12.5g} {:>12.5g}\n", name, a.get<double>(),
                               b.get<double>());
    };
    row("porosity", c["cmc"]["porosity"], c["nodal"]["porosity"]);
    row("mean curvature std (1/" + units + ")", c["cmc"]["mean_curvature_std"],
        c["nodal"]["mean_curvature_std"]);
    row("specific surface (1/" + units + ")", c["cmc"]["specific_surface"],
        c["nodal"]["specific_surface"]);
    if (c["cmc"].contains("wall_thickness")) {
      row("wall thickness mean (" + units + ")", c["cmc"]["wall_thickness"]["mean"],
          c["nodal"]["wall_thickness"]["mean"]);
      row("wall thickness std (" + units + ")", c["cmc"]["wall_thickness"]["std"],
          c["nodal"]["wall_thickness"]["std"]);
      row("pore size std (" + units + ")", c["cmc"]["pore_size"]["std"],
          c["nodal"]["pore_size"]["std"]);
      // The thinnest wall and narrowest pore: where the CMC part's evenness shows.
      for (const auto& [key, name] : {std::pair{"wall_thickness", "wall thickness"},
                                      {"pore_size", "pore size"}})
        for (const char* stat : {"min", "p5"})
          if (c["cmc"][key].contains(stat))
            row(fmt::format("{} {} ({})", name, stat, units), c["cmc"][key][stat],
                c["nodal"][key][stat]);
      if (c["cmc"].contains("throat"))
        row("throat min (" + units + ")", c["cmc"]["throat"], c["nodal"]["throat"]);
    }
    if (c["cmc"].contains("thickness"))
      row("sheet thickness (" + units + ")", c["cmc"]["thickness"], c["nodal"]["thickness"]);
  }
  if (r.contains("properties")) {
    // One line per solid: the CMC cell, then its nodal twins when compared.
    const auto& pj = r["properties"];
    auto line = [&](const std::string& name, const nlohmann::json& p) {
      auto m3 = [&](const char* key) {  // mean of x, y, z or of a tensor's diagonal
        const auto& v = p[key];
        return v[0].is_array() ? (v[0][0].get<double>() + v[1][1].get<double>() +
                                  v[2][2].get<double>()) / 3.0
                               : (v[0].get<double>() + v[1].get<double>() +
                                  v[2].get<double>()) / 3.0;
      };
      std::string text = fmt::format("{:<13} solid fraction {:.4f}", name,
                                     p["relative_density"].get<double>());
      if (p.contains("youngs_modulus"))
        text += fmt::format("; E/E_s {:.4g} (min {:.4g}, max {:.4g}), G/E_s {:.4g}, nu {:.3g}, "
                            "Zener {:.3g}, HS bulk {:.2f}",
                            m3("youngs_modulus"), p["youngs_modulus_min"].get<double>(),
                            p["youngs_modulus_max"].get<double>(), m3("shear_modulus"),
                            m3("poisson_ratio"), p["zener_ratio"].get<double>(),
                            p["fraction_of_bound"]["bulk_modulus"].get<double>());
      if (p.contains("youngs_modulus_gpa"))
        text += fmt::format(", E {:.4g} GPa", m3("youngs_modulus_gpa"));
      if (p.contains("conductivity_solid"))
        text += fmt::format("; k_solid/k_s {:.4g} (HS {:.2f}), k_pore {:.4g}",
                            m3("conductivity_solid"),
                            p["fraction_of_bound"]["conductivity_solid"].get<double>(),
                            m3("conductivity_pore"));
      std::cerr << text << "\n";
      for (const auto& w : p["warnings"])
        std::cerr << fmt::format("warning ({}): {}\n", name, w.get<std::string>());
    };
    std::cerr << fmt::format("unit cell properties (--properties, {:.1f} s; / the solid's E_s, "
                             "k_s; mean of x, y, z):\n",
                             pj["properties_seconds"].get<double>());
    line("CMC " + o.solid, pj);
    if (pj.contains("nodal")) line("nodal", pj["nodal"]);
    if (pj.contains("nodal_offset")) line("nodal offset", pj["nodal_offset"]);
  }
  if (r["design"].contains("achieved")) print_design(r["design"], units);
  if (r.contains("decimation")) {
    const auto& dm = r["decimation"];
    if (dm["applied"].get<bool>())
      std::cerr << fmt::format(
          "decimated {} -> {} triangles ({} -> {} bytes as binary STL; error {:.3g} {}, "
          "volume {:+.2e})\n",
          dm["triangles_before"].get<long>(), dm["triangles_after"].get<long>(),
          dm["stl_bytes_before"].get<long>(), dm["stl_bytes_after"].get<long>(),
          dm["error"].get<double>(), units, dm["volume_change"].get<double>());
    else
      std::cerr << fmt::format("not decimated ({} triangles): {}\n",
                               dm["triangles_before"].get<long>(), dm["note"].get<std::string>());
  }
  // Where the time went (FILE.json's seconds, wall clock): the stages of a second or more,
  // longest first, so that the cost of the defaults (decimation, page, part measures) shows.
  std::vector<std::pair<double, std::string>> stages;
  for (const auto& [key, value] : r["seconds"].items())
    if (value.is_number() && value.get<double>() >= 1.0)
      stages.emplace_back(value.get<double>(), key);
  std::sort(stages.rbegin(), stages.rend());
  if (!stages.empty()) {
    std::string line = "seconds (wall):";
    for (const auto& [seconds, key] : stages) line += fmt::format(" {} {:.1f},", key, seconds);
    line.pop_back();
    std::cerr << line << "\n";
  }
  std::cerr << fmt::format("wrote {} ({} bytes) and {}.json\n", run.out.string(),
                           std::filesystem::file_size(run.out), run.out.string());
}

int run_scaffold(ScaffoldCommand& cmd) {
  ScaffoldOptions o = cmd.options;
  for (const auto& [key, option] : cmd.given)
    if (option->count() > 0) o.given.insert(key);
  RunChoices choices = cmd.strings.choices;
  for (const auto& [option, cli] : cmd.strings.options)
    if (cli->count() > 0) choices.given.insert(option->key);
  auto progress = std::make_shared<Progress>(cmd.quiet);
  ScaffoldContext ctx;
  if (!cmd.quiet) ctx.say = [](const std::string& line) { std::cerr << line << "\n"; };
  ctx.step = [progress](const StepRecord& s) { progress->step(s); };
  ctx.steps_done = [progress] { progress->finish(); };
  ctx.decimate = decimate_progress(cmd);
  ScaffoldRun run;
  try {
    // Checked before the thread count is applied, as every option is before any work.
    ctx.threads = apply_threads(cmd.threads);
    run = make_scaffold(o, cmd.params, choices, ctx);
  } catch (const OptionError& e) {
    throw UsageError(e.what());
  }
  if (!run.page.empty() && !cmd.quiet)
    std::cerr << fmt::format("wrote {} and {} in {:.2f} s\n", run.page.string(),
                             run.preview.string(), run.page_seconds);
  if (!cmd.quiet) print_summary(cmd, run);
  for (const std::string& w : run.warnings) std::cerr << "warning: " << w << "\n";
  return 0;
}

}  // namespace

CommandFn add_scaffold_command(CLI::App& root) {
  auto cmd = std::make_shared<ScaffoldCommand>();
  CLI::App* app = root.add_subcommand(
      "scaffold",
      "A printable scaffold from design targets: computes (or reuses from the cache) the CMC "
      "member, trims the lattice to the box, solves a sheet's wall thickness for the porosity, "
      "removes fragments, checks that the pores percolate, measures wall and pore sizes, and "
      "writes FILE with FILE.json\nExample: cmcsurf scaffold --surface G --porosity 0.7 --solid "
      "sheet --cell-size 2 --size 10x10x20 --units mm --grid 32 --fast --out part.3mf");
  // The scaffold's own options from their table (driver/scaffold_run.cpp), defaults shown.
  for (const ScaffoldOption& option : scaffold_option_table()) {
    CLI::Option* added = std::visit(
        [&](auto member) -> CLI::Option* {
          auto& value = cmd->options.*member;
          using T = std::remove_reference_t<decltype(value)>;
          if constexpr (std::is_same_v<T, bool>) {
            return app->add_flag(option.cli, value, option.help);
          } else {
            CLI::Option* a = app->add_option(option.cli, value, option.help);
            bool shown = true;
            if constexpr (std::is_same_v<T, std::string>) shown = !value.empty();
            else shown = std::isfinite(double(value)) && value != T(0);
            if (shown) a->capture_default_str();
            return a;
          }
        },
        option.member);
    if (option.key == "out") added->required();
    cmd->given.emplace_back(option.key, added);
  }
  add_run_options(*app, cmd->params, cmd->strings, false);
  // The part's lattice is the member's grid tiled: a scaffold's default grid is its own.
  if (CLI::Option* grid = app->get_option_no_throw("--grid")) {
    grid->description(fmt::format(
        "Cells per side N of the member (m * 2^k, m in {{1,3,5,7}}, N >= 8); the part's lattice "
        "spacing is --cell-size / N (default {} in the fast mode, {} with --paper; "
        "--resolution sets it in --units instead)",
        kScaffoldGrid, kPaperGrid));
    grid->default_str(std::to_string(kScaffoldGrid));
  }
  add_threads_option(*app, cmd->threads);
  app->add_flag("--quiet", cmd->quiet, "No progress or summary output");
  return {app, [cmd]() -> int { return run_scaffold(*cmd); }};
}

}  // namespace cmcsurf::cli
