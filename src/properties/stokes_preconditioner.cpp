#include "properties/stokes_preconditioner.h"

#include <fftw3.h>
#include <omp.h>

#include <cmath>
#include <complex>
#include <stdexcept>

#include "grid/check.h"
#include "properties/fft_preconditioner.h"  // planner_mutex

namespace cmcsurf::properties {

struct StokesFftPlans {
  fftw_plan forward = nullptr, backward = nullptr;
  fftw_complex* spectrum = nullptr;
  std::size_t spectrum_size = 0;
  ~StokesFftPlans() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    if (forward) fftw_destroy_plan(forward);
    if (backward) fftw_destroy_plan(backward);
    fftw_free(spectrum);
  }
};

StokesPreconditioner::StokesPreconditioner(const StokesOperator& op, double sigma,
                                           VelocityPreconditioner velocity,
                                           const VelocityMultigridOptions& multigrid)
    : op_(op), sigma_(sigma), pressure_weight_(op.cells()), cos_(op.n()),
      plans_(std::make_unique<StokesFftPlans>()) {
  if (!(sigma > 0.0)) throw std::invalid_argument("Stokes preconditioner: sigma must be > 0");
  const int n = op.n();
  for (int m = 0; m < n; ++m) cos_[m] = std::cos(2.0 * M_PI * m / n);
  const int nh = n / 2 + 1;
  const std::size_t m = op.cells();
  // 1 / (mu sum over the voxel's faces of a^2 / A_qq): the inverse of B diag(A)^-1 B^T's
  // diagonal, 1 / mu in the open fluid.
  const std::vector<float>& diag = op.velocity_diagonal();
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t q = (std::size_t(k) * n + j) * n + i;
        const std::size_t up[3] = {(std::size_t(k) * n + j) * n + (i + 1) % n,
                                   (std::size_t(k) * n + (j + 1) % n) * n + i,
                                   (std::size_t((k + 1) % n) * n + j) * n + i};
        double sum = 0.0;
        for (int c = 0; c < 3; ++c)
          for (std::size_t f : {q, up[c]}) {
            const double a = op.face_area(c, f);
            if (a > 0.0) sum += a * a / double(diag[c * m + f]);
          }
        pressure_weight_[q] = sum > 0.0 ? float(1.0 / (op.viscosity() * sum)) : 0.0f;
      }
  if (velocity == VelocityPreconditioner::multigrid) {
    multigrid_ = std::make_unique<VelocityMultigrid>(op, sigma, multigrid);
    return;
  }
  plans_->spectrum_size = std::size_t(n) * n * nh;
  plans_->spectrum = fftw_alloc_complex(plans_->spectrum_size);
  double* real = fftw_alloc_real(m);
  init_fftw_threads();
  {
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftw_plan_with_nthreads(omp_get_max_threads());
    // One component at a time (a third of the spectrum's memory); FFTW_UNALIGNED because
    // the components start at multiples of n^3 doubles.
    plans_->forward = fftw_plan_dft_r2c_3d(n, n, n, real, plans_->spectrum,
                                           FFTW_ESTIMATE | FFTW_UNALIGNED);
    plans_->backward = fftw_plan_dft_c2r_3d(n, n, n, plans_->spectrum, real,
                                            FFTW_ESTIMATE | FFTW_UNALIGNED);
  }
  fftw_free(real);
  CMCSURF_CHECK(plans_->forward && plans_->backward);
}

StokesPreconditioner::~StokesPreconditioner() = default;

std::size_t StokesPreconditioner::bytes() const {
  return plans_->spectrum_size * sizeof(fftw_complex) + pressure_weight_.size() * sizeof(float) +
         (multigrid_ ? multigrid_->bytes() : 0);
}

double StokesPreconditioner::scale(std::size_t q) const {
  const float d = op_.velocity_diagonal()[q];
  return d > 0.0f ? std::sqrt(6.0 / double(d)) : 0.0;
}

double StokesPreconditioner::symbol(int kx, int ky, int kz) const {
  const double l = 6.0 - 2.0 * (cos_[kx] + cos_[ky] + cos_[kz]);
  return 1.0 / (op_.viscosity() * (l + sigma_));
}

void StokesPreconditioner::apply(const double* r, double* z) const {
  const int n = op_.n(), nh = n / 2 + 1;
  const std::size_t m = op_.cells();
  const float* w = pressure_weight_.data();
  if (multigrid_) {
    multigrid_->apply(r, z);
#pragma omp parallel for schedule(static)
    for (std::size_t q = 0; q < m; ++q) z[3 * m + q] = w[q] * r[3 * m + q];
    return;
  }
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < 3 * m; ++q) z[q] = scale(q) * r[q];
  auto* v = reinterpret_cast<std::complex<double>*>(plans_->spectrum);
  const double norm = 1.0 / double(m);
  for (int c = 0; c < 3; ++c) {
    fftw_execute_dft_r2c(plans_->forward, z + c * m, plans_->spectrum);
#pragma omp parallel for schedule(static)
    for (int kz = 0; kz < n; ++kz)
      for (int ky = 0; ky < n; ++ky)
        for (int kx = 0; kx < nh; ++kx)
          v[(std::size_t(kz) * n + ky) * nh + kx] *= norm * symbol(kx, ky, kz);
    fftw_execute_dft_c2r(plans_->backward, plans_->spectrum, z + c * m);
  }
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < m; ++q) {
    for (int c = 0; c < 3; ++c) z[c * m + q] *= scale(c * m + q);
    z[3 * m + q] = w[q] * r[3 * m + q];
  }
}

void StokesPreconditioner::apply_ref(const double* r, double* z) const {
  CMCSURF_CHECK(!multigrid_);
  const int n = op_.n();
  const std::size_t m = op_.cells();
  std::vector<std::complex<double>> a(m), b(m);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t q = 0; q < m; ++q) a[q] = scale(c * m + q) * r[c * m + q];
    auto dft = [&](int axis, double sign) {
      const std::size_t stride = axis == 0 ? 1 : axis == 1 ? std::size_t(n) : std::size_t(n) * n;
      for (std::size_t q = 0; q < m; ++q) {
        const std::size_t k = q / stride % n, base = q - k * stride;
        std::complex<double> sum = 0.0;
        for (int t = 0; t < n; ++t)
          sum += a[base + t * stride] * std::polar(1.0, sign * 2.0 * M_PI * double(k) * t / n);
        b[q] = sum;
      }
      a.swap(b);
    };
    for (int axis = 0; axis < 3; ++axis) dft(axis, -1.0);
    for (int kz = 0; kz < n; ++kz)
      for (int ky = 0; ky < n; ++ky)
        for (int kx = 0; kx < n; ++kx) a[(std::size_t(kz) * n + ky) * n + kx] *= symbol(kx, ky, kz);
    for (int axis = 0; axis < 3; ++axis) dft(axis, 1.0);
    for (std::size_t q = 0; q < m; ++q)
      z[c * m + q] = scale(c * m + q) * a[q].real() / double(m);
  }
  for (std::size_t q = 0; q < m; ++q) z[3 * m + q] = double(pressure_weight_[q]) * r[3 * m + q];
}

}  // namespace cmcsurf::properties
