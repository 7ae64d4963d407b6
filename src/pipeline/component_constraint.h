// --constrain components and --structure double: a volume per connected component of phase 1
// (two networks in a matrix keep theirs, so they relax to equal H instead of ripening into
// one), the seed of a double structure, and the warnings about a seed's topology.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "grid/field.h"
#include "measure/components.h"
#include "model/run.h"

namespace cmcsurf {

struct RunParams;
struct Measures;

// Thrown when phase 1's component count changes under --constrain components (two networks
// merged, or one pinched off): the constraint's labels no longer describe the field.
class ComponentsChanged : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The Lagrange multipliers of --constrain components, one per component of phase 1 of the
// field it was made from: after each time step, phi += lambda_c w in component c's region
// (measure/components.h), w = 4 phi (1 - phi) (the interface layer, so the bulk stays put),
// with lambda_c by secant steps until the sharp volume of the region's phase 1 is its target.
// The targets are the components' sharp volumes at the start scaled to sum to alpha. Whole
// grid only.
class ComponentConstraint {
 public:
  // targets: given (a resumed run's, one per component), or empty to take them from phi.
  ComponentConstraint(const Field& phi, double alpha, const std::vector<double>& targets = {});
  // phi: ghost >= 2, halo current; leaves it current.
  void project(Field& phi) const;
  // Throws ComponentsChanged naming `step` when phase 1 no longer has count() components.
  void check_count(const Field& phi, int step) const;
  std::vector<double> volumes(const Field& phi) const;
  const std::vector<double>& targets() const { return targets_; }
  int count() const { return labels_.count; }

 private:
  void project_component(Field& phi, int c) const;  // halo current before and after
  ComponentLabels labels_;
  std::vector<double> targets_;
};

// The seed of --structure double: phase 1 where |F| > c (F the nodal formula of params.surface
// without its +1/2 offset), c such that its sharp volume fraction is params.volume_fraction,
// with the equilibrium tanh profile at params.epsilon (surfaces/nodal_level.h). Ghost 2.
Field double_structure_seed(const RunParams& params);

// phi: halo current.
PhaseTopology phase_topology(const Field& phi);
PhaseTopology phase_topology(const Measures& m);

// The warnings of a run whose seed (the field step 6 starts from) had `seed` and whose result
// has `final`: the topology changed, or the seed has several components that share one volume
// constraint (they can exchange volume: --constrain components holds each).
std::vector<std::string> topology_warnings(const PhaseTopology& seed, const PhaseTopology& final,
                                           const RunParams& params);

}  // namespace cmcsurf
