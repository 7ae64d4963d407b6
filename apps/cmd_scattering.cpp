// cmcsurf scattering: structure factors, space group, powder pattern and peak indexing of a
// computed field (docs/science.md, "Scattering").
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.h"
#include "commands.h"
#include "run_control.h"
#include "common/wall_clock.h"
#include "common/atomic_file.h"
#include "io/csv.h"
#include "io/json_file.h"
#include "io/png.h"
#include "mesh_options.h"
#include "science/saxs_plot.h"
#include "science/scattering.h"

namespace cmcsurf::cli {

namespace {

struct ScatteringCommand {
  std::string from;
  std::string density = "step";
  int smax = 0;  // 0: min(100, what the grid resolves)
  double lattice = 1.0;
  std::string peaks;
  double debye_waller = 0.0;
  double peak_width = 0.0;
  std::string peak_shape = "gaussian";
  double absent_tol = 1e-6;
  double index_tol = 0.01;
  std::string out;
  int threads = 0;
  bool quiet = false;
};

std::vector<double> parse_peaks(const std::string& text) {
  std::vector<double> peaks;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double q = 0;
    try {
      q = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(q) || q <= 0)
      throw UsageError(fmt::format(
          "--peaks: '{}' is not a peak position; accepted: q1,q2,... in 1/nm, each > 0", item));
    peaks.push_back(q);
  }
  if (peaks.size() < 2)
    throw UsageError("--peaks: give at least 2 peak positions (q1,q2,... in 1/nm) to index");
  return peaks;
}


}  // namespace

CommandFn add_scattering_command(CLI::App& root) {
  auto cmd = std::make_shared<ScatteringCommand>();
  CLI::App* app = root.add_subcommand(
      "scattering",
      "Structure factors F_hkl of a density model of a computed field by FFT, the cubic space "
      "group its absences imply, the SAXS powder pattern and the indexing of measured peaks "
      "(reflections.csv, saxs.csv, saxs.png, scattering.json)\nExample: cmcsurf scattering "
      "--from gyroid50 --density bilayer:0.05 --lattice 12 --peaks 0.80,0.93");
  app->add_option("--from", cmd->from, "Run directory (with field.vti) or a .vti/.pvti file")
      ->required();
  app->add_option("--density", cmd->density,
                  "Density model: step (1 where phi > 1/2), bilayer:L (1 within L unit cells of "
                  "the surface, 0 < L < 0.25) or profile (phi itself)")
      ->capture_default_str();
  app->add_option("--smax", cmd->smax,
                  "Largest s = h^2 + k^2 + l^2 (1 <= S <= (N/2 - 1)^2; 0: min(100, that))")
      ->capture_default_str();
  app->add_option("--lattice", cmd->lattice, "Lattice parameter a of the unit cell, nm (> 0)")
      ->capture_default_str();
  app->add_option("--peaks", cmd->peaks,
                  "Measured peak positions q1,q2,... (1/nm, at least 2) to index");
  app->add_option("--debye-waller", cmd->debye_waller,
                  "Debye-Waller sigma, nm: intensities times exp(-sigma^2 q^2) (>= 0)")
      ->capture_default_str();
  app->add_option("--peak-width", cmd->peak_width,
                  "Peak FWHM in 1/nm (>= 0; 0: 1% of the first peak's q)")
      ->capture_default_str();
  app->add_option("--peak-shape", cmd->peak_shape, "gaussian or lorentzian")
      ->capture_default_str();
  app->add_option("--absent-tol", cmd->absent_tol,
                  "A class is absent below this fraction of the strongest intensity (0 < T < 1)")
      ->capture_default_str();
  app->add_option("--index-tol", cmd->index_tol,
                  "Indexing: largest relative residual |q - q_fit| / q accepted (0 < T < 1)")
      ->capture_default_str();
  app->add_option("--out", cmd->out, "Output directory (default: the run folder's scattering/)");
  add_threads_option(*app, cmd->threads);
  app->add_flag("--quiet", cmd->quiet, "No summary output");
  return {app, [cmd]() -> int {
            const auto t0 = WallClock::now();
            DensityParams density;
            try {
              density = parse_density_model(cmd->density);
            } catch (const std::invalid_argument& e) {
              throw UsageError(fmt::format("--density: {}", e.what()));
            }
            if (!(std::isfinite(cmd->lattice) && cmd->lattice > 0))
              throw UsageError(fmt::format("--lattice: got {}; accepted: > 0 (nm)", cmd->lattice));
            if (!(std::isfinite(cmd->debye_waller) && cmd->debye_waller >= 0))
              throw UsageError(
                  fmt::format("--debye-waller: got {}; accepted: >= 0 (nm)", cmd->debye_waller));
            if (!(std::isfinite(cmd->peak_width) && cmd->peak_width >= 0))
              throw UsageError(
                  fmt::format("--peak-width: got {}; accepted: >= 0 (1/nm)", cmd->peak_width));
            if (cmd->peak_shape != "gaussian" && cmd->peak_shape != "lorentzian")
              throw UsageError(fmt::format("--peak-shape: got '{}'; accepted: gaussian, lorentzian",
                                           cmd->peak_shape));
            for (const auto& [name, v] : {std::pair{"--absent-tol", cmd->absent_tol},
                                          std::pair{"--index-tol", cmd->index_tol}})
              if (!(v > 0 && v < 1))
                throw UsageError(fmt::format("{}: got {}; accepted: 0 < value < 1", name, v));
            if (cmd->smax < 0)
              throw UsageError(
                  fmt::format("--smax: got {}; accepted: >= 1 (0: default)", cmd->smax));
            std::vector<double> peaks;
            if (!cmd->peaks.empty()) peaks = parse_peaks(cmd->peaks);
            const Field phi = load_phi(cmd->from, "--from");
            const int n = phi.n();
            const int max_smax = (n / 2 - 1) * (n / 2 - 1);
            if (cmd->smax > max_smax)
              throw UsageError(fmt::format(
                  "--smax: got {}; accepted on this {}^3 grid: 1 <= S <= {} (indices up to {})",
                  cmd->smax, n, max_smax, n / 2 - 1));
            const int smax = cmd->smax > 0 ? cmd->smax : std::min(100, max_smax);
            double lo = INFINITY, hi = -INFINITY;
            for (int k = 0; k < n; ++k)
              for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i)
                  lo = std::min(lo, phi(i, j, k)), hi = std::max(hi, phi(i, j, k));
            if (!(lo < 0.5 && hi > 0.5))
              throw UsageError(fmt::format(
                  "--from: '{}' has no phi = 1/2 surface (phi in [{:.6g}, {:.6g}])", cmd->from, lo,
                  hi));
            const std::filesystem::path from(cmd->from);
            const std::filesystem::path out =
                !cmd->out.empty() ? std::filesystem::path(cmd->out)
                : std::filesystem::is_directory(from) ? from / "scattering"
                                                       : from.parent_path() / "scattering";
            const double load_s = seconds_since(t0);
            apply_threads(cmd->threads);

            ScatteringParams sp;
            sp.density = density;
            sp.smax = smax;
            sp.absent_tol = cmd->absent_tol;
            sp.powder.lattice = cmd->lattice;
            sp.powder.debye_waller = cmd->debye_waller;
            sp.powder.peak_width = cmd->peak_width;
            sp.powder.lorentzian = cmd->peak_shape == "lorentzian";
            sp.peaks = peaks;
            sp.index_tol = cmd->index_tol;
            ScatteringResult result;
            try {
              result = scattering_analysis(phi, sp);
            } catch (const std::invalid_argument& e) {
              throw UsageError(fmt::format("--peaks: {}", e.what()));  // the rest is checked
            }
            const auto& classes = result.classes;
            const SpaceGroupFit& fit = result.space_group;
            const PowderPattern& pattern = result.powder;
            // Outputs.
            CsvWriter reflections({"h", "k", "l", "s", "multiplicity", "intensity", "amplitude",
                                   "phase"});
            for (const auto& r : classes)
              reflections.add_row({r.h, r.k, r.l, r.s, r.multiplicity, r.intensity, r.amplitude,
                                   r.phase});
            CsvWriter saxs({"q", "intensity"});
            for (std::size_t i = 0; i < pattern.q.size(); ++i)
              saxs.add_row({pattern.q[i], pattern.intensity[i]});
            nlohmann::json report = {{"source", cmd->from}};
            report.update(scattering_json(result, sp));
            report["timings"]["load_seconds"] = load_s;
            const nlohmann::json indexing = report.value("indexing", nlohmann::json());
            std::filesystem::path name = from.lexically_normal();  // the title: its last name
            if (name.filename().empty()) name = name.parent_path();
            const Image plot = draw_saxs_plot(
                pattern, fmt::format("{}: {} density, {}", name.filename().string(),
                                     density_model_name(density), fit.best->symbol));
            // Ours (new, empty or cmcsurf's) and one writer at a time (io/output_folder.h);
            // scattering.json last, as the mark of a complete folder.
            const FolderClaim claim = claim_folder(out, {.kind = "scattering", .option = "--out"},
                                                   *Decomposition::world());
            reflections.save(out / "reflections.csv");
            saxs.save(out / "saxs.csv");
            write_png(out / "saxs.png", plot);
            write_json_atomic(out / "scattering.json", report);
            if (!cmd->quiet) {
              std::vector<int> allowed_s;
              for (const auto& r : classes)
                if (r.present && (allowed_s.empty() || allowed_s.back() != r.s))
                  allowed_s.push_back(r.s);
              if (allowed_s.size() > 10) allowed_s.resize(10);
              std::cerr << fmt::format(
                  "{} density on {}^3: space group {}{} ({} consistent); first allowed s: {}\n",
                  density_model_name(density), n, fit.best->symbol,
                  fit.divisor > 1 ? fmt::format(" on a cell 1/{} of the box", fit.divisor) : "",
                  fit.consistent.size(), fmt::join(allowed_s, ", "));
              if (!indexing.is_null())
                std::cerr << fmt::format("indexed {} peaks: a = {:.6g} nm, rms residual {:.3g}\n",
                                         peaks.size(), indexing["lattice_nm"].get<double>(),
                                         indexing["rms_relative_residual"].get<double>());
              std::cerr << fmt::format("wrote {}/reflections.csv, saxs.csv, saxs.png, "
                                       "scattering.json\n", out.string());
            }
            return 0;
          }};
}

}  // namespace cmcsurf::cli
