#include "properties/voxel_operator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "grid/check.h"

namespace cmcsurf::properties {

namespace {

// The 8 nodes of voxel (i, j, k), corner order of voxel_element.h.
inline void voxel_nodes(int n, int i, int j, int k, std::size_t nodes[8]) {
  const int ip = i + 1 == n ? 0 : i + 1, jp = j + 1 == n ? 0 : j + 1, kp = k + 1 == n ? 0 : k + 1;
  const std::size_t nn = std::size_t(n);
  const std::size_t z0 = nn * nn * k, z1 = nn * nn * kp, y0 = nn * j, y1 = nn * jp;
  nodes[0] = z0 + y0 + i;
  nodes[1] = z0 + y0 + ip;
  nodes[2] = z0 + y1 + i;
  nodes[3] = z0 + y1 + ip;
  nodes[4] = z1 + y0 + i;
  nodes[5] = z1 + y0 + ip;
  nodes[6] = z1 + y1 + i;
  nodes[7] = z1 + y1 + ip;
}

// f(voxel index, s_e, nodes) for every voxel with s_e != 0; layers of voxels in two colours
// (even, odd) run in parallel, so voxels of one pass share no node; an odd n's last layer,
// which touches layer 0's nodes, runs in a third pass.
// A voxel is solid when s > 0 and s >= void_below.
inline bool is_solid(double s, double void_below) { return s > 0.0 && s >= void_below; }

template <class F>
void for_each_solid_voxel_coloured(int n, const double* s, double void_below, F f) {
  const int paired = n - (n & 1);
  auto layer = [&](int k) {
    std::size_t nodes[8];
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t e = std::size_t(n) * (std::size_t(n) * k + j) + i;
        if (!is_solid(s[e], void_below)) continue;
        voxel_nodes(n, i, j, k, nodes);
        f(e, s[e], nodes);
      }
  };
  for (int colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(static)
    for (int k = colour; k < paired; k += 2) layer(k);
  }
  if (paired != n) layer(n - 1);
}

}  // namespace

template <int D>
VoxelOperator<D>::VoxelOperator(int n, const std::vector<double>& s, const ElementMatrix& ke,
                                double void_below)
    : n_(n), s_(&s), void_below_(void_below), ke_(ke), active_(std::size_t(n) * n * n, 0) {
  CMCSURF_CHECK(n >= 2 && s.size() == nodes());
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t e = std::size_t(n) * (std::size_t(n) * k + j) + i;
        if (!(s[e] >= 0.0 && s[e] <= 1.0))
          throw std::invalid_argument("solid fraction must lie in [0, 1]");
        if (!is_solid(s[e], void_below)) continue;
        std::size_t nd[8];
        voxel_nodes(n, i, j, k, nd);
        for (std::size_t a : nd) active_[a] = 1;
      }
}

template <int D>
std::vector<float> VoxelOperator<D>::node_scaling() const {
  const int n = n_;
  std::vector<float> d(nodes(), 0.0f);
  std::vector<double> w(nodes(), 0.0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        std::size_t nd[8];
        voxel_nodes(n, i, j, k, nd);
        const double se = (*s_)[nd[0]];
        if (is_solid(se, void_below_))
          for (std::size_t a : nd) w[a] += se / 8.0;
      }
  for (std::size_t q = 0; q < d.size(); ++q)
    if (active_[q]) d[q] = float(1.0 / std::sqrt(w[q]));
  return d;
}

template <int D>
void VoxelOperator<D>::apply(const double* x, double* y) const {
  const std::size_t m = size();
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < m; ++q) y[q] = 0.0;
  const ElementMatrix& ke = ke_;
  for_each_solid_voxel_coloured(n_, s_->data(), void_below_, [&](std::size_t, double se,
                                                    const std::size_t* nodes) {
    alignas(64) double xe[kElementDofs], ye[kElementDofs];
    for (int a = 0; a < 8; ++a)
      for (int c = 0; c < D; ++c) xe[D * a + c] = x[D * nodes[a] + c];
    for (int r = 0; r < kElementDofs; ++r) ye[r] = 0.0;
    for (int b = 0; b < kElementDofs; ++b) {  // K symmetric: column b = row b
      const double xb = se * xe[b];
      for (int r = 0; r < kElementDofs; ++r) ye[r] += ke[b][r] * xb;
    }
    for (int a = 0; a < 8; ++a)
      for (int c = 0; c < D; ++c) y[D * nodes[a] + c] += ye[D * a + c];
  });
}

template <int D>
void VoxelOperator<D>::apply_ref(const double* x, double* y) const {
  const int n = n_;
  for (std::size_t q = 0; q < size(); ++q) y[q] = 0.0;
  auto node = [n](int i, int j, int k) {
    return std::size_t(((k % n) * n + j % n) * n + i % n);
  };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double sv = (*s_)[node(i, j, k)];
        const double se = sv > 0.0 && sv >= void_below_ ? sv : 0.0;
        for (int a = 0; a < 8; ++a)
          for (int ca = 0; ca < D; ++ca) {
            double sum = 0.0;
            for (int b = 0; b < 8; ++b)
              for (int cb = 0; cb < D; ++cb)
                sum += ke_[D * a + ca][D * b + cb] *
                       x[D * node(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2 & 1)) + cb];
            y[D * node(i + (a & 1), j + (a >> 1 & 1), k + (a >> 2 & 1)) + ca] += se * sum;
          }
      }
}

template <int D>
void VoxelOperator<D>::add_element_vector(const ElementVector& fe, double scale, double* b) const {
  for_each_solid_voxel_coloured(n_, s_->data(), void_below_, [&](std::size_t, double se,
                                                    const std::size_t* nodes) {
    for (int a = 0; a < 8; ++a)
      for (int c = 0; c < D; ++c) b[D * nodes[a] + c] += scale * se * fe[D * a + c];
  });
}

template <int D>
std::array<std::array<double, 3>, D> VoxelOperator<D>::weighted_mean_gradient(
    const double* x) const {
  const int n = n_;
  const double* s = s_->data();
  double g[D * 3] = {};
#pragma omp parallel for schedule(static) reduction(+ : g[:D * 3])
  for (int k = 0; k < n; ++k) {
    std::size_t nodes[8];
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t e = std::size_t(n) * (std::size_t(n) * k + j) + i;
        if (!is_solid(s[e], void_below_)) continue;
        voxel_nodes(n, i, j, k, nodes);
        for (int a = 0; a < 8; ++a)
          for (int c = 0; c < D; ++c) {
            const double w = s[e] * 0.25 * x[D * nodes[a] + c];
            for (int d = 0; d < 3; ++d) g[3 * c + d] += (a >> d & 1) ? w : -w;
          }
      }
  }
  std::array<std::array<double, 3>, D> out{};
  for (int c = 0; c < D; ++c)
    for (int d = 0; d < 3; ++d) out[c][d] = g[3 * c + d] / double(nodes());
  return out;
}

template <int D>
double VoxelOperator<D>::mean_solid_fraction() const {
  double sum = 0.0;
  const double* s = s_->data();
  const std::size_t m = nodes();
  const double cut = void_below_;
#pragma omp parallel for schedule(static) reduction(+ : sum)
  for (std::size_t e = 0; e < m; ++e) sum += is_solid(s[e], cut) ? s[e] : 0.0;
  return sum / double(m);
}

template <int D>
double VoxelOperator<D>::removed_solid_fraction() const {
  double sum = 0.0;
  for (double v : *s_) sum += is_solid(v, void_below_) ? 0.0 : v;
  return sum / double(nodes());
}

template class VoxelOperator<1>;
template class VoxelOperator<3>;

}  // namespace cmcsurf::properties
