#include "pipeline/run_outputs.h"

#include <chrono>

#include "common/wall_clock.h"
#include "pipeline/sweep.h"
#include "surfaces/initial.h"

namespace cmcsurf {

CmcQuality run_quality(const Field& psi, const RunParams& p, const RunResult& r,
                       const std::vector<CurvatureSample>* samples) {
  // The final sharp volume fraction (measure_field's) is the relaxed field's own.
  return measure_cmc_quality_psi(psi, r.final.volume_fraction, p, samples);
}

RunOutputs run_outputs(const Field& phi, const RunParams& p, const RunResult& r,
                       std::optional<FinalFieldCache> cache, bool preview, bool page) {
  RunOutputs out;
  const auto t0 = WallClock::now();
  const bool kept = cache && cache->psi.n() == phi.n() && cache->psi.size() == phi.size();
  const Field psi = kept ? std::move(cache->psi) : profile_inverse(phi);
  const std::vector<CurvatureSample> samples =
      kept ? std::move(cache->samples) : std::vector<CurvatureSample>();
  cache.reset();
  out.quality = run_quality(psi, p, r, kept ? &samples : nullptr);
  out.quality.seconds = seconds_since(t0);
  if (preview) out.preview = make_run_preview(psi, p, r, out.quality);
  if (page) {
    const auto t1 = WallClock::now();
    out.page = preview_surfaces(psi, p.surface, out.quality.nodal_level, r.final.mean_curvature,
                                kPageCells, out.quality.has_nodal);
    out.page_seconds = seconds_since(t1);
  }
  return out;
}

}  // namespace cmcsurf
