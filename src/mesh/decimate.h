// Mesh-size control for printed parts (docs/scaffolds.md): quadric edge-collapse decimation,
// by our own priority-queue collapser (mesh/edge_collapse.h: decimate_solid) or by OpenMesh's
// decimater (Debian libopenmesh-dev: decimate_solid_ref, the reference the tests compare
// with; minutes on a 5M-triangle part), which with a tolerance also refuses collapses that
// move samples of the input further than it (a sampled Hausdorff module, decimate.cpp). Both
// refuse collapses that would break the manifold (link condition) and keep the box's edges.
// A result is accepted only while the solid stays closed, manifold, as many pieces, with its
// volume within a tolerance and the symmetric error measured within the tolerance; otherwise
// the budget is relaxed (or the tolerance halved) and it retries.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/tri_mesh.h"

namespace cmcsurf {

struct DecimateParams {
  std::size_t max_triangles = 0;  // 0: no triangle budget
  double tolerance = 0.0;         // chordal error bound in mesh units (0: none)
  double max_volume_change = 5e-3;  // relative
  // The error is measured on at most this many sample points per side, every k-th one when
  // there are more (0: all). Then it estimates the error and bounds nothing.
  std::size_t max_error_samples = 0;
};

struct Decimated {
  TriMesh mesh;
  std::size_t triangles_before = 0, triangles_after = 0;
  // Symmetric: the larger of the largest distances from points on the input to the result
  // and from points on the result to the input, each triangle split into similar ones with
  // edges of at most sample_spacing (about the input's mean edge) and their corners taken. The
  // distance to a surface is 1-Lipschitz and every point of a triangle is within its longest
  // edge / sqrt(3) of a corner, so the Hausdorff distance between the two surfaces is at most
  // error + sample_spacing / sqrt(3).
  double error = 0.0;
  double error_input_to_output = 0.0, error_output_to_input = 0.0;
  double sample_spacing = 0.0;
  std::size_t sample_stride = 1;  // > 1: the error is measured on every k-th sample only
  double module_tolerance = 0.0;  // the sampled Hausdorff module's bound in the accepted attempt
  double volume_change = 0.0;  // relative
  int attempts = 0;            // 0: nothing to do (the input is within the budget)
  // false: no attempt passed the checks, or none was needed; mesh is the input
  bool applied = false;
  bool within_budget = false;  // triangles_after <= max_triangles (or no budget)
  std::string note;            // why nothing was applied
  double seconds = 0.0;
  double error_seconds = 0.0;  // of which measuring the error
  std::string method;          // which decimator (decimated_json's `method`)
  // Each attempt's triangles and measured error (-1: failed a check before the measure).
  std::vector<std::size_t> attempt_triangles;
  std::vector<double> attempt_errors;
};

// Progress of a decimation: the stage, the attempt (0: within one) and the triangles left
// (collapse) or of the result being measured (measure).
enum class DecimateStage { kCollapse, kMeasure };
using DecimateProgress =
    std::function<void(DecimateStage stage, int attempt, std::size_t triangles)>;

// The larger of the two one-sided sampled distances between a and b (Decimated::error) and
// the sample spacing; exposed for the tests.
struct SymmetricDistance {
  double a_to_b = 0.0, b_to_a = 0.0, spacing = 0.0;
  std::size_t stride = 1;  // every stride-th sample was measured (1: all)
};
SymmetricDistance symmetric_distance(const TriMesh& a, const TriMesh& b,
                                     std::size_t max_samples = 0);

// Components of the mesh by shared vertices (surface shells).
std::size_t mesh_shell_count(const TriMesh& m);

// Throws std::invalid_argument when neither a budget nor a tolerance is given. A budget at or
// above the input's triangle count (and no tolerance) returns the input at once. With a
// tolerance the collapses stop at a quadric error of it (each vertex within it of the planes
// of the input triangles merged into it) and the measured error decides.
Decimated decimate_solid(const TriMesh& m, const DecimateParams& p,
                         const DecimateProgress& progress = {});

// The reference: OpenMesh's decimater with the same checks (and with a tolerance the sampled
// Hausdorff module at half of it, the caps' outlines and creases locked).
Decimated decimate_solid_ref(const TriMesh& m, const DecimateParams& p);

nlohmann::json decimated_json(const Decimated& d, const DecimateParams& p,
                              const std::string& units);

}  // namespace cmcsurf
