#include "pipeline/component_constraint.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "measure/sharp_volume.h"
#include "measure/topology.h"
#include "pipeline/cmc.h"
#include "surfaces/nodal_level.h"

namespace cmcsurf {

namespace {

// Below this the secant stops: round-off of a sum over N^3 cells.
constexpr double kVolumeRoundOff = 1e-13;
constexpr int kMaxSecantSteps = 8;
constexpr int kSweeps = 2;

// Component c's sharp volume in phi + lambda w, w = 4 phi (1 - phi) in c's region.
double region_volume(const Field& phi, const ComponentLabels& labels, int c, double lambda) {
  const int n = phi.n();
  Field f(n, 2);
  std::size_t q = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i, ++q) {
        const double v = phi(i, j, k);
        f(i, j, k) = labels.region[q] == c ? v + lambda * std::max(0.0, 4.0 * v * (1.0 - v)) : v;
      }
  f.exchange_halo();
  return component_volumes(f, labels)[std::size_t(c)];
}

}  // namespace

ComponentConstraint::ComponentConstraint(const Field& phi, double alpha,
                                         const std::vector<double>& targets)
    : labels_(label_components(phi, 1)) {
  if (labels_.count == 0)
    throw std::invalid_argument("--constrain components: phase 1 is empty at the start");
  if (targets.size() == std::size_t(labels_.count)) {
    targets_ = targets;
    return;
  }
  targets_ = volumes(phi);
  double sum = 0.0;
  for (double v : targets_) sum += v;
  for (double& v : targets_) v *= alpha / sum;
}

std::vector<double> ComponentConstraint::volumes(const Field& phi) const {
  return component_volumes(phi, labels_);
}

void ComponentConstraint::project(Field& phi) const {
  // A component's correction moves its neighbours' volumes only through the dual cells at
  // the regions' borders (round-off for a resolved matrix): a second sweep takes that up.
  for (int sweep = 0; sweep < kSweeps; ++sweep)
    for (int c = 0; c < labels_.count; ++c) project_component(phi, c);
  phi.exchange_halo();
}

void ComponentConstraint::project_component(Field& phi, int c) const {
  const int n = phi.n();
  const double cell = 1.0 / phi.global_cells();
  const double target = targets_[std::size_t(c)];
  // First slope: across a tanh layer the integral of w along the normal is the layer's
  // width 4 sqrt2 eps, so the volume moves by lambda times the sum of w over the region.
  double slope = 0.0;
  std::size_t q = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i, ++q)
        if (labels_.region[q] == c) {
          const double v = phi(i, j, k);
          slope += std::max(0.0, 4.0 * v * (1.0 - v)) * cell;
        }
  double l0 = 0.0, v0 = region_volume(phi, labels_, c, 0.0);
  if (std::abs(v0 - target) <= kVolumeRoundOff || !(slope > 0.0)) return;
  double l1 = (target - v0) / slope, v1 = region_volume(phi, labels_, c, l1);
  for (int it = 0; it < kMaxSecantSteps && std::abs(v1 - target) > kVolumeRoundOff; ++it) {
    const double s = (v1 - v0) / (l1 - l0);
    if (!(s > 0.0) || !std::isfinite(s)) break;
    l0 = l1;
    v0 = v1;
    l1 += (target - v1) / s;
    v1 = region_volume(phi, labels_, c, l1);
  }
  q = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i, ++q)
        if (labels_.region[q] == c) {
          double& v = phi(i, j, k);
          v += l1 * std::max(0.0, 4.0 * v * (1.0 - v));
        }
  phi.exchange_halo();
}

void ComponentConstraint::check_count(const Field& phi, int step) const {
  const std::int64_t now = phase_components(phi).phase1;
  if (now == labels_.count) return;
  throw ComponentsChanged(fmt::format(
      "--constrain components: phase 1 had {} connected components at the start and {} after "
      "time step {} ({}); each held its own volume, so the surface itself changed: a layer "
      "between them thinner than the interface (a finer --grid or a smaller --epsilon), or a "
      "component too thin for its volume to stay connected",
      labels_.count, now, step,
      now < labels_.count ? "components merged or one dissolved" : "a component split"));
}

Field double_structure_seed(const RunParams& params) {
  const NodalLevelSet nodal =
      double_level_set(params.surface, params.volume_fraction, params.grid);
  return nodal_tanh_profile(nodal, params.epsilon);
}

PhaseTopology phase_topology(const Field& phi) {
  const PhaseComponents c = phase_components(phi);
  return {c.phase1, c.phase2, euler_characteristic(phi), euler_characteristic_phase2(phi)};
}

PhaseTopology phase_topology(const Measures& m) {
  return {m.components_phase1, m.components_phase2, m.euler_characteristic,
          m.euler_characteristic_phase2};
}

std::vector<std::string> topology_warnings(const PhaseTopology& seed, const PhaseTopology& final,
                                           const RunParams& params) {
  std::vector<std::string> out;
  auto describe = [](const PhaseTopology& t) {
    return fmt::format("phase 1 in {} components (chi {}), phase 2 in {} (chi {})",
                       t.components_phase1, t.euler_characteristic_phase1, t.components_phase2,
                       t.euler_characteristic_phase2);
  };
  if (!(seed == final))
    out.push_back(fmt::format("the result's topology differs from its seed's: the seed had {}, "
                              "the result has {}",
                              describe(seed), describe(final)));
  if (params.constrain != Constraint::kComponents && seed.components_phase1 > 1)
    out.push_back(fmt::format(
        "the seed's phase 1 has {} components that share one volume constraint (--constrain "
        "{}): they can exchange volume and ripen into fewer; --constrain components holds each",
        seed.components_phase1, constraint_name(params.constrain)));
  return out;
}

}  // namespace cmcsurf
