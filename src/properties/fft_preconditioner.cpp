#include "properties/fft_preconditioner.h"

#include <fftw3.h>
#include <omp.h>

#include <cmath>
#include <mutex>

#include "grid/check.h"

namespace cmcsurf::properties {

std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

void init_fftw_threads() {
  static std::once_flag once;
  std::call_once(once, [] { fftw_init_threads(); });
}

struct FftPlans {
  fftw_plan forward = nullptr, backward = nullptr;
  fftw_complex* spectrum = nullptr;
  std::size_t spectrum_size = 0;
  ~FftPlans() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    if (forward) fftw_destroy_plan(forward);
    if (backward) fftw_destroy_plan(backward);
    fftw_free(spectrum);
  }
};

FftReferencePreconditioner::FftReferencePreconditioner(int n, int dofs, double lambda0,
                                                       double mu0,
                                                       const std::vector<float>* scaling)
    : n_(n), dofs_(dofs), lambda0_(lambda0), mu0_(mu0), scaling_(scaling), cos_(n), sin_(n),
      plans_(std::make_unique<FftPlans>()) {
  CMCSURF_CHECK(n >= 2 && (dofs == 1 || dofs == 3));
  CMCSURF_CHECK(!scaling || scaling->size() == std::size_t(n) * n * n);
  for (int m = 0; m < n; ++m) {
    cos_[m] = std::cos(2.0 * M_PI * m / n);
    sin_[m] = std::sin(2.0 * M_PI * m / n);
  }
  const int nh = n / 2 + 1;
  plans_->spectrum_size = std::size_t(n) * n * nh * dofs;
  plans_->spectrum = fftw_alloc_complex(plans_->spectrum_size);
  double* real = fftw_alloc_real(std::size_t(n) * n * n * dofs);
  init_fftw_threads();
  {
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftw_plan_with_nthreads(omp_get_max_threads());
    const int dims[3] = {n, n, n}, cdims[3] = {n, n, nh};
    plans_->forward = fftw_plan_many_dft_r2c(3, dims, dofs, real, dims, dofs, 1,
                                             plans_->spectrum, cdims, dofs, 1, FFTW_ESTIMATE);
    plans_->backward = fftw_plan_many_dft_c2r(3, dims, dofs, plans_->spectrum, cdims, dofs, 1,
                                              real, dims, dofs, 1, FFTW_ESTIMATE);
  }
  fftw_free(real);
  CMCSURF_CHECK(plans_->forward && plans_->backward);
}

FftReferencePreconditioner::~FftReferencePreconditioner() = default;

std::size_t FftReferencePreconditioner::bytes() const {
  return plans_->spectrum_size * sizeof(fftw_complex);
}

void FftReferencePreconditioner::solve_symbol(int kx, int ky, int kz,
                                              std::complex<double>* v) const {
  const double cx = cos_[kx], cy = cos_[ky], cz = cos_[kz];
  const double mx = (2.0 + cx) / 3.0, my = (2.0 + cy) / 3.0, mz = (2.0 + cz) / 3.0;
  const double pxx = (2.0 - 2.0 * cx) * my * mz, pyy = (2.0 - 2.0 * cy) * mx * mz,
               pzz = (2.0 - 2.0 * cz) * mx * my;
  const double trace = pxx + pyy + pzz;
  if (trace <= 0.0) {  // the mean
    for (int c = 0; c < dofs_; ++c) v[c] = 0.0;
    return;
  }
  if (dofs_ == 1) {
    v[0] /= trace;
    return;
  }
  const double sx = sin_[kx], sy = sin_[ky], sz = sin_[kz];
  const double lm = lambda0_ + mu0_, mt = mu0_ * trace;
  const double a = lm * pxx + mt, b = lm * pyy + mt, c = lm * pzz + mt;
  const double d = lm * sx * sy * mz, e = lm * sx * sz * my, f = lm * sy * sz * mx;
  // [[a d e] [d b f] [e f c]]^-1 by cofactors
  const double i00 = b * c - f * f, i01 = e * f - d * c, i02 = d * f - b * e;
  const double i11 = a * c - e * e, i12 = d * e - a * f, i22 = a * b - d * d;
  const double inv = 1.0 / (a * i00 + d * i01 + e * i02);
  const std::complex<double> v0 = v[0], v1 = v[1], v2 = v[2];
  v[0] = inv * (i00 * v0 + i01 * v1 + i02 * v2);
  v[1] = inv * (i01 * v0 + i11 * v1 + i12 * v2);
  v[2] = inv * (i02 * v0 + i12 * v1 + i22 * v2);
}

void FftReferencePreconditioner::apply(const double* r, double* z) const {
  const int n = n_, nh = n / 2 + 1, dofs = dofs_;
  const std::size_t nodes = std::size_t(n) * n * n;
  const float* d = scaling_ ? scaling_->data() : nullptr;
  const double* in = r;
  if (d) {  // z = D r, transformed in place of r
#pragma omp parallel for schedule(static)
    for (std::size_t q = 0; q < nodes; ++q)
      for (int c = 0; c < dofs; ++c) z[dofs * q + c] = d[q] * r[dofs * q + c];
    in = z;
  }
  fftw_execute_dft_r2c(plans_->forward, const_cast<double*>(in), plans_->spectrum);
  auto* spec = reinterpret_cast<std::complex<double>*>(plans_->spectrum);
  const double scale = 1.0 / double(nodes);
#pragma omp parallel for schedule(static)
  for (int kz = 0; kz < n; ++kz)
    for (int ky = 0; ky < n; ++ky)
      for (int kx = 0; kx < nh; ++kx) {
        std::complex<double>* v = spec + dofs * ((std::size_t(kz) * n + ky) * nh + kx);
        solve_symbol(kx, ky, kz, v);
        for (int c = 0; c < dofs; ++c) v[c] *= scale;
      }
  fftw_execute_dft_c2r(plans_->backward, plans_->spectrum, z);
  if (d) {
#pragma omp parallel for schedule(static)
    for (std::size_t q = 0; q < nodes; ++q)
      for (int c = 0; c < dofs; ++c) z[dofs * q + c] *= d[q];
  }
}

void FftReferencePreconditioner::apply_ref(const double* r, double* z) const {
  const int n = n_, dofs = dofs_;
  const std::size_t nodes = std::size_t(n) * n * n;
  std::vector<std::complex<double>> a(nodes * dofs), b(nodes * dofs);
  auto weight = [&](std::size_t q) { return scaling_ ? double((*scaling_)[q]) : 1.0; };
  for (std::size_t q = 0; q < nodes * dofs; ++q) a[q] = weight(q / dofs) * r[q];
  // One direct DFT along axis `axis` (stride of that axis in nodes), sign -1 forward.
  auto dft = [&](int axis, double sign) {
    const std::size_t stride = axis == 0 ? 1 : axis == 1 ? std::size_t(n) : std::size_t(n) * n;
    for (std::size_t q = 0; q < nodes; ++q) {
      const std::size_t m = q / stride % n, base = q - m * stride;
      for (int c = 0; c < dofs; ++c) {
        std::complex<double> sum = 0.0;
        for (int t = 0; t < n; ++t)
          sum += a[dofs * (base + t * stride) + c] *
                 std::polar(1.0, sign * 2.0 * M_PI * double(m) * t / n);
        b[dofs * q + c] = sum;
      }
    }
    a.swap(b);
  };
  for (int axis = 0; axis < 3; ++axis) dft(axis, -1.0);
  for (int kz = 0; kz < n; ++kz)
    for (int ky = 0; ky < n; ++ky)
      for (int kx = 0; kx < n; ++kx) solve_symbol(kx, ky, kz, &a[dofs * ((kz * n + ky) * n + kx)]);
  for (int axis = 0; axis < 3; ++axis) dft(axis, 1.0);
  for (std::size_t q = 0; q < nodes; ++q)
    for (int c = 0; c < dofs; ++c)
      z[dofs * q + c] = weight(q) * a[dofs * q + c].real() / double(nodes);
}

}  // namespace cmcsurf::properties
