// report.json and history.csv of a run (the names and keys are a contract with users' scripts).
#pragma once

#include <cstdint>

#include <concepts>
#include <filesystem>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "measure/quality.h"
#include "model/run.h"
#include "schema/report_schema.h"

namespace cmcsurf {

// A value read from a JSON file (report.json, a checkpoint's or sweep.json's keys) as T, checked
// instead of converted: an integer type takes only a JSON integer inside T's range (4294967298
// is not an int, -1 not a seed, 2.5 not a count), a floating type any number, bool a boolean,
// std::string a string. Anything else throws std::runtime_error "<what>: got ...; accepted: ...".
template <class T>
T json_value(const nlohmann::json& v, const std::string& what) {
  auto refuse = [&](const std::string& accepted) {
    const std::string got = v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    throw std::runtime_error(fmt::format("{}: got {}; accepted: {}", what, got, accepted));
  };
  if constexpr (std::same_as<T, bool>) {
    if (!v.is_boolean()) refuse("true or false");
    return v.get<bool>();
  } else if constexpr (std::integral<T>) {
    using L = std::numeric_limits<T>;
    const std::string range = fmt::format("an integer in [{}, {}]", L::min(), L::max());
    if (v.is_number_unsigned()) {
      const auto u = v.get<std::uint64_t>();
      if (u > static_cast<std::make_unsigned_t<T>>(L::max())) refuse(range);
      return static_cast<T>(u);
    }
    if (!v.is_number_integer()) refuse(range);
    const auto s = v.get<std::int64_t>();
    const bool fits = s < 0 ? std::is_signed_v<T> && s >= std::int64_t(L::min())
                            : std::uint64_t(s) <= std::uint64_t(L::max());
    if (!fits) refuse(range);
    return static_cast<T>(s);
  } else if constexpr (std::floating_point<T>) {
    if (!v.is_number()) refuse("a number");
    return v.get<T>();
  } else {
    static_assert(std::same_as<T, std::string>, "json_value: bool, integer, float or string");
    if (!v.is_string()) refuse("a string");
    return v.get<std::string>();
  }
}

// Every parameter of a run, as the command line names them.
nlohmann::json params_json(const RunParams& p);
// The inverse of params_json (a checkpoint's or sweep.json's parameters): every key must be
// present with its type, except that keys missing from a sweep's shared parameters (surface,
// volume_fraction) keep `base`'s values, and every value must pass the command line's range
// checks (check_run_params). Throws std::runtime_error naming the bad key or range.
RunParams params_from_json(const nlohmann::json& j, const RunParams& base = {});
// The measures' keys (NaN as null). curvature_integrals: the keys from the surface's Gaussian
// curvature and H^2 (homogeneity_index, gaussian_curvature_integral, gauss_bonnet_error,
// mean_gaussian_curvature, willmore_energy); off for the truncated nodal start, whose psi jumps
// where the truncation cut phi and whose K is then no estimate of anything.
nlohmann::json measures_json(const Measures& m, bool curvature_integrals = true);

// The report: the required keys at top level (surface, grid, epsilon, dt,
// volume_fraction_target, steps, vcycles, converged, area, mean_curvature, mean_curvature_mu,
// total_mean_curvature, volume_fraction, mass, energy, wall_seconds, version) plus details
// and "parameters".
nlohmann::json run_report(const RunParams& p, const RunResult& r, int threads);
// Peak resident memory of this process so far (report.json's peak_memory_bytes).
std::uint64_t peak_memory_bytes();

// A step's stage as history.csv, the checkpoint's history and Python write it: "relax", or
// "relax@16@32" for a step of the coarse-to-fine continuation taken on grid 16 (of a run on 64).
std::string stage_text(const StepRecord& r);
// The value of one of history.csv's columns (schema/report_schema.h) of a step.
using HistoryValue = std::variant<long long, std::string, double>;
HistoryValue history_value(const StepRecord& r, HistoryColumn c);
// The inverse, for a checkpoint's history: sets column c of r from its JSON value (the stage's
// text as stage_text writes it). Throws std::runtime_error naming the column on a wrong type or
// an unknown stage.
void set_history_value(StepRecord& r, HistoryColumn c, const nlohmann::json& v);

// history.csv: one row per step, history_column_table()'s columns in their formats. The text
// is also the run page's (report/run_page.h), which a run hands it without reading the file.
std::string history_csv(const std::vector<StepRecord>& history);
void write_history_csv(const std::filesystem::path& path, const std::vector<StepRecord>& history);

// CMC quality keys merged into report.json (docs/families.md): mean_curvature_std, area_iso,
// nodal_area, nodal_area_iso, nodal_mean_curvature, nodal_mean_curvature_std,
// nodal_area_excess (nodal_area / area - 1), nodal_area_excess_iso, ...; nodal keys are null
// for surfaces without a nodal formula.
nlohmann::json quality_json(const CmcQuality& q, double relaxed_area);
// curvature_histogram.csv: H_lo, H_hi, relaxed, nodal (area fraction per bin of local H); its
// text, as history_csv's, is also the run page's.
std::string curvature_histogram_csv(const CmcQuality& q);
void write_curvature_histogram_csv(const std::filesystem::path& path, const CmcQuality& q);
// The relaxed surface's H and K distributions, each on its own range: bin, H_lo, H_hi,
// H_fraction, K_lo, K_hi, K_fraction (area fractions).
void write_curvature_distribution_csv(const std::filesystem::path& path, const CmcQuality& q);

// sweep.csv: one row per report, a column per top-level scalar of the reports (strings, numbers,
// booleans; null is an empty cell), sweep_leading_columns() first.
std::string sweep_csv(const std::vector<nlohmann::json>& reports);

}  // namespace cmcsurf
