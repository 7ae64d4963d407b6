// The stages after a solve that the run folder shows (docs/performance.md, "The whole
// command"): the CMC quality comparison, preview.png's picture and report.html's meshes, all
// from one psi = atanh(2 phi - 1) of the final field. `cmcsurf run`, `sweep` and Python's
// Result.save() call this, then write; each stage's wall time goes into report.json.
#pragma once

#include <optional>

#include "measure/quality.h"
#include "pipeline/cmc.h"
#include "pipeline/preview.h"

namespace cmcsurf {

struct RunOutputs {
  CmcQuality quality;                   // quality_seconds (psi included)
  std::optional<RunPreview> preview;    // preview_seconds
  std::optional<PreviewSurfaces> page;  // report.html's meshes at kPageCells: page_seconds
  double page_seconds = 0.0;
};

// phi: the final field of r (r.phi: the whole grid, or this process's block under MPI, when
// every process calls it and rank 0 gets the preview and the page). The quality stage always
// runs; the preview and the page's meshes when asked for. `cache`: the final measures' psi and
// samples that the run returned beside r (taken over here, so that they are freed with the
// outputs' own); without it they are computed.
RunOutputs run_outputs(const Field& phi, const RunParams& p, const RunResult& r,
                       std::optional<FinalFieldCache> cache, bool preview, bool page);
// The quality stage alone, from a given psi and, if given, its surface's samples (Python takes
// the quality with the run, the pictures when it saves).
CmcQuality run_quality(const Field& psi, const RunParams& p, const RunResult& r,
                       const std::vector<CurvatureSample>* samples = nullptr);

}  // namespace cmcsurf
