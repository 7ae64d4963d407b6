#include "measure/components.h"

#include <stdexcept>

#include "measure/sharp_surface.h"
#include "measure/sharp_volume.h"
#include "measure/topology.h"
#include "measure/whole_surface.h"

namespace cmcsurf {

namespace {

// The 26 neighbours.
struct Offsets {
  int d[26][3];
  Offsets() {
    int m = 0;
    for (int z = -1; z <= 1; ++z)
      for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
          if (x || y || z) {
            d[m][0] = x;
            d[m][1] = y;
            d[m][2] = z;
            ++m;
          }
  }
};

}  // namespace

ComponentLabels label_components(const Field& phi, int phase, double level) {
  if (!phi.whole()) throw std::invalid_argument("label_components: needs the whole grid");
  if (phase != 1 && phase != 2) throw std::invalid_argument("label_components: phase 1 or 2");
  static const Offsets kNeighbours;
  const int n = phi.n();
  const std::size_t cells = std::size_t(n) * n * n;
  ComponentLabels out;
  out.n = n;
  out.phase = phase;
  out.component.assign(cells, -1);
  out.region.assign(cells, -1);
  const auto id = [n](int i, int j, int k) {
    return std::size_t((std::size_t((k + n) % n) * n + (j + n) % n) * n + (i + n) % n);
  };
  const auto in = [&](int i, int j, int k) {
    const double v = phi(i, j, k);
    return phase == 1 ? v > level : v < level;
  };
  // Flood fill of each component (26-connected), then the regions grow from all of them at
  // once, one 26-neighbour layer per pass of the queue: ties go to the earlier component.
  std::vector<std::size_t> queue;
  queue.reserve(cells);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t c0 = id(i, j, k);
        if (out.component[c0] >= 0 || !in(i, j, k)) continue;
        const std::int32_t label = out.count++;
        std::size_t head = queue.size();
        out.component[c0] = label;
        queue.push_back(c0);
        while (head < queue.size()) {
          const std::size_t c = queue[head++];
          const int ci = int(c % n), cj = int((c / n) % n), ck = int(c / (std::size_t(n) * n));
          for (const auto& d : kNeighbours.d) {
            const int a = (ci + d[0] + n) % n, b = (cj + d[1] + n) % n, e = (ck + d[2] + n) % n;
            const std::size_t nb = id(a, b, e);
            if (out.component[nb] < 0 && in(a, b, e)) {
              out.component[nb] = label;
              queue.push_back(nb);
            }
          }
        }
      }
  for (std::size_t c : queue) out.region[c] = out.component[c];
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::size_t c = queue[head];
    const int ci = int(c % n), cj = int((c / n) % n), ck = int(c / (std::size_t(n) * n));
    for (const auto& d : kNeighbours.d) {
      const std::size_t nb = id(ci + d[0], cj + d[1], ck + d[2]);
      if (out.region[nb] < 0) {
        out.region[nb] = out.region[c];
        queue.push_back(nb);
      }
    }
  }
  return out;
}

Field component_field(const Field& phi, const ComponentLabels& labels, int c) {
  if (!phi.whole() || phi.n() != labels.n)
    throw std::invalid_argument("component_field: the labels' whole grid");
  const int n = phi.n();
  Field out(n, 2);
  std::size_t q = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i, ++q) {
        const std::int32_t label = labels.component[q];
        out(i, j, k) = label >= 0 && label != c ? 1.0 - phi(i, j, k) : phi(i, j, k);
      }
  out.exchange_halo();
  return out;
}

std::vector<double> component_volumes(const Field& phi, const ComponentLabels& labels) {
  if (!phi.whole() || phi.n() != labels.n)
    throw std::invalid_argument("component_volumes: the labels' whole grid");
  const int n = phi.n();
  Field psi = Field::like(phi, 1);
  curvature_corrected(phi, psi);
  Field fraction = Field::like(phi, 1);
  dual_cell_fractions(psi, 0.5, fraction);
  const double sign = labels.phase == 1 ? 1.0 : -1.0;
  std::vector<double> sums(std::size_t(labels.count), 0.0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        // The corner deepest in the labelled phase names the dual cell's region.
        int bi = i, bj = j, bk = k;
        double best = -2.0;
        for (int c = 0; c < 8; ++c) {
          const int a = i + (c & 1), b = j + ((c >> 1) & 1), d = k + ((c >> 2) & 1);
          const double v = sign * phi(a, b, d);
          if (v > best) {
            best = v;
            bi = a % n;
            bj = b % n;
            bk = d % n;
          }
        }
        const std::int32_t r = labels.region[(std::size_t(bk) * n + bj) * n + bi];
        const double f = labels.phase == 1 ? fraction(i, j, k) : 1.0 - fraction(i, j, k);
        if (r >= 0) sums[std::size_t(r)] += f;
      }
  for (double& v : sums) v /= phi.global_cells();
  return sums;
}

namespace {

// The phase whose components interface_measures lists.
int labelled_phase(const PhaseComponents& counts) {
  return counts.phase2 > counts.phase1 ? 2 : 1;
}

std::vector<InterfaceMeasures> interfaces_labelled(const Field& phi, int phase) {
  const ComponentLabels labels = label_components(phi, phase);
  std::vector<InterfaceMeasures> out;
  for (int c = 0; c < labels.count; ++c) {
    const Field f = component_field(phi, labels, c);
    Field psi = Field::like(f, 2);
    tanh_profile_inverse(f, psi);
    const LevelSetSurface s = level_set_surface(psi);
    InterfaceMeasures m;
    m.phase = phase;
    m.component = c;
    m.area = s.area;
    m.mean_curvature = s.mean_curvature;
    m.mean_curvature_std = s.mean_curvature_std;
    m.gaussian_curvature_integral = s.gaussian_curvature_integral;
    // chi(boundary of M) = 2 chi(M) for a compact 3-manifold M.
    m.euler_characteristic =
        2 * (phase == 1 ? euler_characteristic(f) : euler_characteristic_phase2(f));
    out.push_back(m);
  }
  const std::vector<double> volumes = component_volumes(phi, labels);
  for (int c = 0; c < labels.count; ++c) out[std::size_t(c)].enclosed_volume = volumes[c];
  return out;
}

}  // namespace

std::vector<InterfaceMeasures> interface_measures(const Field& phi) {
  return interfaces_labelled(phi, labelled_phase(phase_components(phi)));
}

std::vector<InterfaceMeasures> interface_measures(const Field& phi,
                                                  const WholeSurfaceMeasures& whole) {
  const int phase = labelled_phase(whole.counts);
  const std::int64_t count = phase == 1 ? whole.counts.phase1 : whole.counts.phase2;
  if (count != 1) return interfaces_labelled(phi, phase);
  // One component: component_field(phi, labels, 0) is phi itself and every cell's region is 0.
  InterfaceMeasures m;
  m.phase = phase;
  m.component = 0;
  m.area = whole.surface.area;
  m.mean_curvature = whole.surface.mean_curvature;
  m.mean_curvature_std = whole.surface.mean_curvature_std;
  m.gaussian_curvature_integral = whole.surface.gaussian_curvature_integral;
  m.euler_characteristic = 2 * (phase == 1 ? whole.euler_phase1 : whole.euler_phase2);
  m.enclosed_volume = phase == 1 ? whole.volume_fraction : 1.0 - whole.volume_fraction;
  return {m};
}

}  // namespace cmcsurf
