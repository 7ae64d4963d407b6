#include "science/scattering.h"

#include <fftw3.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <set>
#include <stdexcept>

#include "common/wall_clock.h"
#include "measure/sharp_volume.h"

namespace cmcsurf {

namespace {

constexpr double kPi = std::numbers::pi;

int wrap(int i, int n) { return ((i % n) + n) % n; }

// The interior of a whole-grid field as a flat periodic array, x fastest.
std::vector<double> flatten(const Field& f) {
  const int n = f.n();
  std::vector<double> out(std::size_t(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) out[(std::size_t(k) * n + j) * n + i] = f(i, j, k);
  return out;
}

// g - h^2 (Lap g + mean over the 4 body diagonals of the second difference) / 24: the
// symmetric form of measure/sharp_volume.h's bias correction (the Kuhn interpolant exceeds a
// quadratic by h^2 (Lap + d.H.d) / 24 on average; over all 4 diagonals d.H.d averages to Lap).
std::vector<double> bias_corrected(const std::vector<double>& g, int n) {
  std::vector<double> psi(g.size());
  auto at = [&](int i, int j, int k) {
    return g[(std::size_t(wrap(k, n)) * n + wrap(j, n)) * n + wrap(i, n)];
  };
  static const int diag[4][3] = {{1, 1, 1}, {-1, 1, 1}, {1, -1, 1}, {1, 1, -1}};
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double c = at(i, j, k);
        const double lap = at(i + 1, j, k) + at(i - 1, j, k) + at(i, j + 1, k) +
                           at(i, j - 1, k) + at(i, j, k + 1) + at(i, j, k - 1) - 6 * c;
        double dd = 0;
        for (const auto& d : diag)
          dd += at(i + d[0], j + d[1], k + d[2]) + at(i - d[0], j - d[1], k - d[2]) - 2 * c;
        psi[(std::size_t(k) * n + j) * n + i] = c - (lap + dd / 4) / 24;
      }
  return psi;
}

// Fraction of the dual cube with corner values g[c] (c = x + 2y + 4z) where the piecewise-
// linear interpolant exceeds `level`, averaged over the Kuhn splits along the 4 diagonals.
double cube_fraction_above(const double g[8], double level) {
  static const int perms[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4},
                                  {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  static const int flips[4] = {0, 1, 2, 4};
  bool above = false, below = false;
  for (int c = 0; c < 8; ++c) (g[c] > level ? above : below) = true;
  if (!below) return 1.0;
  if (!above) return 0.0;
  double sum = 0;
  for (int m : flips)
    for (const auto& p : perms) {
      const int v[4] = {0, p[0], p[0] + p[1], 7};
      double t[4];
      for (int a = 0; a < 4; ++a) t[a] = g[v[a] ^ m] - level;
      sum += tet_fraction_above(t);
    }
  return sum / 24;
}

// Per dual cell (i, j, k) (the cube between centres i..i+1 ...): fraction above each level,
// combined as sum_m sign_m * fraction(level_m).
std::vector<double> dual_fractions(const std::vector<double>& psi, int n,
                                   const std::vector<std::pair<double, double>>& terms) {
  std::vector<double> out(psi.size());
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        double g[8];
        for (int c = 0; c < 8; ++c)
          g[c] = psi[(std::size_t(wrap(k + (c >> 2), n)) * n + wrap(j + ((c >> 1) & 1), n)) * n +
                     wrap(i + (c & 1), n)];
        double v = 0;
        for (const auto& [level, sign] : terms) v += sign * cube_fraction_above(g, level);
        out[(std::size_t(k) * n + j) * n + i] = v;
      }
  return out;
}

// w of phi = (1 + tanh(d / w)) / 2: mean of (1 - t^2) / (2 |grad phi|), t = 2 phi - 1, over
// the cells with |t| < 1/2 (central differences).
double tanh_width(const std::vector<double>& phi, int n) {
  auto at = [&](int i, int j, int k) {
    return phi[(std::size_t(wrap(k, n)) * n + wrap(j, n)) * n + wrap(i, n)];
  };
  double sum = 0;
  long count = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double t = 2 * at(i, j, k) - 1;
        if (std::abs(t) >= 0.5) continue;
        const double gx = (at(i + 1, j, k) - at(i - 1, j, k)) * n / 2;
        const double gy = (at(i, j + 1, k) - at(i, j - 1, k)) * n / 2;
        const double gz = (at(i, j, k + 1) - at(i, j, k - 1)) * n / 2;
        const double grad = std::sqrt(gx * gx + gy * gy + gz * gz);
        if (grad <= 0) continue;
        sum += (1 - t * t) / (2 * grad);
        ++count;
      }
  if (count == 0) throw std::runtime_error("the field has no cells near its phi = 1/2 surface");
  return sum / double(count);
}

double sinc(double x) { return x == 0 ? 1.0 : std::sin(x) / x; }

}  // namespace

DensityParams parse_density_model(const std::string& text) {
  DensityParams p;
  if (text == "step") return p;
  if (text == "profile") {
    p.model = DensityModel::kProfile;
    return p;
  }
  if (text.rfind("bilayer:", 0) == 0) {
    const std::string value = text.substr(8);
    std::size_t used = 0;
    double L = 0;
    try {
      L = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == value.size() && used > 0 && std::isfinite(L) && L > 0 && L < 0.25) {
      p.model = DensityModel::kBilayer;
      p.half_thickness = L;
      return p;
    }
  }
  throw std::invalid_argument(fmt::format(
      "'{}' is not a density model: step, profile or bilayer:L with the half-thickness L in "
      "(0, 0.25) unit cells",
      text));
}

std::string density_model_name(const DensityParams& p) {
  switch (p.model) {
    case DensityModel::kStep: return "step";
    case DensityModel::kProfile: return "profile";
    case DensityModel::kBilayer: return fmt::format("bilayer:{:g}", p.half_thickness);
  }
  return "?";
}

DensityGrid density_from_phase_field(const Field& phi, const DensityParams& p) {
  if (!phi.whole()) throw std::invalid_argument("density_from_phase_field needs a whole grid");
  DensityGrid rho;
  rho.n = phi.n();
  const int n = rho.n;
  std::vector<double> values = flatten(phi);
  if (p.model == DensityModel::kProfile) {
    rho.values = std::move(values);
    rho.shift = 0.5;
    rho.voxel_average = false;
    return rho;
  }
  rho.shift = 1.0;  // dual cell (i, j, k) is centred on the corner (i + 1) / N
  rho.voxel_average = true;
  if (p.model == DensityModel::kStep) {
    for (double& v : values) v -= 0.5;
    rho.values = dual_fractions(bias_corrected(values, n), n, {{0.0, 1.0}});
    return rho;
  }
  const double w = tanh_width(values, n);
  rho.interface_width = w;
  constexpr double kMaxT = 1 - 1e-12;
  for (double& v : values) v = w * std::atanh(std::clamp(2 * v - 1, -kMaxT, kMaxT));
  const double L = p.half_thickness;
  rho.values = dual_fractions(bias_corrected(values, n), n, {{-L, 1.0}, {L, -1.0}});
  return rho;
}

StructureFactors::StructureFactors(const DensityGrid& rho) : n_(rho.n) {
  const int n = n_;
  if (n < 4 || rho.values.size() != std::size_t(n) * n * n)
    throw std::invalid_argument("StructureFactors: a density grid of n^3 values, n >= 4");
  std::vector<double> in = rho.values;
  const int nh = n / 2 + 1;
  half_.assign(std::size_t(n) * n * nh, {});
  fftw_plan plan;
#pragma omp critical(cmcsurf_fftw_plan)
  plan = fftw_plan_dft_r2c_3d(n, n, n, in.data(), reinterpret_cast<fftw_complex*>(half_.data()),
                              FFTW_ESTIMATE);
  if (!plan) throw std::runtime_error("FFTW could not plan the structure factors' transform");
  fftw_execute(plan);
#pragma omp critical(cmcsurf_fftw_plan)
  fftw_destroy_plan(plan);
  // Layout (z, y, x) with x fastest, so FFTW's last (half) axis is x = h.
  const double scale = 1.0 / (double(n) * n * n);
  for (int l = 0; l < n; ++l)
    for (int k = 0; k < n; ++k)
      for (int h = 0; h < nh; ++h) {
        const int hs = h, ks = k <= n / 2 ? k : k - n, ls = l <= n / 2 ? l : l - n;
        // Samples at (i + shift) / N: F = DFT * exp(-2 pi i (h + k + l) shift / N).
        const double angle = -2 * kPi * (hs + ks + ls) * rho.shift / n;
        std::complex<double> f = half_[(std::size_t(l) * n + k) * nh + h] * scale *
                                 std::polar(1.0, angle);
        if (rho.voxel_average)
          f /= sinc(kPi * hs / n) * sinc(kPi * ks / n) * sinc(kPi * ls / n);
        half_[(std::size_t(l) * n + k) * nh + h] = f;
      }
}

std::complex<double> StructureFactors::operator()(int h, int k, int l) const {
  const int m = max_index();
  if (std::abs(h) > m || std::abs(k) > m || std::abs(l) > m)
    throw std::out_of_range(fmt::format("F({}, {}, {}): indices beyond {} on a {}^3 grid", h, k,
                                        l, m, n_));
  if (h < 0) return std::conj((*this)(-h, -k, -l));
  const int nh = n_ / 2 + 1;
  return half_[(std::size_t(wrap(l, n_)) * n_ + wrap(k, n_)) * nh + h];
}

std::vector<Reflection> reflection_classes(const StructureFactors& f, int smax,
                                           double absent_tol) {
  const int m = f.max_index();
  if (smax < 1 || smax > m * m)
    throw std::invalid_argument(
        fmt::format("smax {} outside [1, {}] (indices up to {} on a {}^3 grid)", smax, m * m, m,
                    f.n()));
  std::vector<Reflection> out;
  for (int h = 1; h * h <= smax; ++h)
    for (int k = 0; k <= h; ++k)
      for (int l = 0; l <= k; ++l) {
        const int s = h * h + k * k + l * l;
        if (s > smax) continue;
        std::set<std::array<int, 3>> orbit;
        int idx[3] = {h, k, l};
        std::sort(idx, idx + 3);
        do {
          for (int signs = 0; signs < 8; ++signs)
            orbit.insert({signs & 1 ? -idx[0] : idx[0], signs & 2 ? -idx[1] : idx[1],
                          signs & 4 ? -idx[2] : idx[2]});
        } while (std::next_permutation(idx, idx + 3));
        Reflection r;
        r.h = h, r.k = k, r.l = l, r.s = s;
        r.multiplicity = int(orbit.size());
        double lo = INFINITY, hi = 0, sum = 0;
        for (const auto& g : orbit) {
          const double i2 = std::norm(f(g[0], g[1], g[2]));
          lo = std::min(lo, i2), hi = std::max(hi, i2), sum += i2;
        }
        r.intensity = sum / r.multiplicity;
        const std::complex<double> rep = f(h, k, l);
        r.amplitude = std::abs(rep);
        r.phase = std::arg(rep);
        r.spread = hi - lo;
        out.push_back(r);
      }
  std::sort(out.begin(), out.end(), [](const Reflection& a, const Reflection& b) {
    return std::tie(a.s, a.h, a.k, a.l) < std::tie(b.s, b.h, b.k, b.l);
  });
  double strongest = 0;
  for (const auto& r : out) strongest = std::max(strongest, r.intensity);
  for (auto& r : out) {
    r.present = strongest > 0 && r.intensity >= absent_tol * strongest;
    r.spread = strongest > 0 ? r.spread / strongest : 0.0;
  }
  return out;
}

const std::vector<SpaceGroup>& cubic_space_groups() {
  // International Tables A, general reflection conditions (hhl and 0kl stand for every
  // permutation and sign of the indices under m-3m).
  static const std::vector<SpaceGroup> groups = {
      {221, "Pm-3m", 48, "P432, P-43m", 'P', 0, 0, 0},
      {222, "Pn-3n", 48, "", 'P', 1, 1, 1},
      {223, "Pm-3n", 48, "", 'P', 0, 1, 1},
      {224, "Pn-3m", 48, "", 'P', 1, 0, 1},
      {225, "Fm-3m", 48, "F432, F-43m", 'F', 0, 0, 0},
      {226, "Fm-3c", 48, "", 'F', 0, 2, 0},
      {227, "Fd-3m", 48, "", 'F', 3, 3, 2},
      {228, "Fd-3c", 48, "", 'F', 3, 2, 2},
      {229, "Im-3m", 48, "I432, I-43m", 'I', 0, 0, 0},
      {230, "Ia-3d", 48, "", 'I', 2, 4, 2},
      {208, "P4_232", 24, "", 'P', 0, 0, 1},
      {210, "F4_132", 24, "", 'F', 0, 0, 2},
      {212, "P4_332", 24, "P4_132", 'P', 0, 0, 2},
      {214, "I4_132", 24, "", 'I', 0, 0, 2},
      {218, "P-43n", 24, "", 'P', 0, 1, 1},
      {219, "F-43c", 24, "", 'F', 0, 2, 0},
      {220, "I-43d", 24, "", 'I', 0, 4, 2},
  };
  return groups;
}

const SpaceGroup& find_space_group(const std::string& symbol) {
  for (const auto& g : cubic_space_groups())
    if (symbol == g.symbol) return g;
  throw std::invalid_argument(fmt::format("unknown cubic space group '{}'", symbol));
}

bool space_group_allows(const SpaceGroup& g, int h, int k, int l) {
  const int x[3] = {std::abs(h), std::abs(k), std::abs(l)};
  auto even = [](int v) { return v % 2 == 0; };
  if (g.centring == 'I' && !even(x[0] + x[1] + x[2])) return false;
  if (g.centring == 'F' && !(even(x[0] + x[1]) && even(x[1] + x[2]))) return false;
  for (int z = 0; z < 3; ++z) {  // 0kl: index z is zero
    if (x[z] != 0) continue;
    const int a = x[(z + 1) % 3], b = x[(z + 2) % 3];
    if (g.c0kl == 1 && !even(a + b)) return false;
    if (g.c0kl == 2 && !(even(a) && even(b))) return false;
    if (g.c0kl == 3 && (a + b) % 4 != 0) return false;
  }
  for (int z = 0; z < 3; ++z) {  // hhl: the other two are equal, l = x[z]
    const int a = x[(z + 1) % 3], b = x[(z + 2) % 3], c = x[z];
    if (a != b) continue;
    if (g.chhl == 1 && !even(c)) return false;
    if (g.chhl == 2 && !(even(a) && even(c))) return false;
    if (g.chhl == 3 && !even(a + c)) return false;
    if (g.chhl == 4 && (2 * a + c) % 4 != 0) return false;
  }
  for (int z = 0; z < 3; ++z) {  // h00: the other two are zero
    if (x[(z + 1) % 3] != 0 || x[(z + 2) % 3] != 0) continue;
    if (g.ch00 == 1 && !even(x[z])) return false;
    if (g.ch00 == 2 && x[z] % 4 != 0) return false;
  }
  return true;
}

SpaceGroupFit detect_space_group(const std::vector<Reflection>& classes) {
  SpaceGroupFit fit;
  int divisor = 0;
  for (const auto& r : classes)
    if (r.present) divisor = std::gcd(divisor, std::gcd(r.h, std::gcd(r.k, r.l)));
  fit.divisor = std::max(divisor, 1);
  std::vector<Reflection> reduced;  // the classes on the reduced cell's lattice
  for (auto r : classes) {
    if (r.h % fit.divisor || r.k % fit.divisor || r.l % fit.divisor) continue;
    r.h /= fit.divisor, r.k /= fit.divisor, r.l /= fit.divisor;
    reduced.push_back(r);
  }
  for (const auto& g : cubic_space_groups()) {
    SpaceGroupCandidate c{&g, 0};
    bool consistent = true;
    for (const auto& r : reduced) {
      if (space_group_allows(g, r.h, r.k, r.l)) continue;
      if (r.present) consistent = false;
      ++c.forbidden;
    }
    if (consistent) fit.consistent.push_back(c);
  }
  if (fit.consistent.empty()) throw std::logic_error("no cubic space group fits (Pm-3m must)");
  std::stable_sort(fit.consistent.begin(), fit.consistent.end(),
                   [](const SpaceGroupCandidate& a, const SpaceGroupCandidate& b) {
                     return std::tie(a.forbidden, a.group->order, a.group->number) >
                            std::tie(b.forbidden, b.group->order, b.group->number);
                   });
  fit.best = fit.consistent.front().group;
  for (const auto& r : reduced)
    if (!r.present && space_group_allows(*fit.best, r.h, r.k, r.l))
      fit.accidental.push_back({r.h, r.k, r.l});
  return fit;
}

PowderPattern powder_pattern(const std::vector<Reflection>& classes, const PowderParams& p) {
  PowderPattern out;
  std::vector<double> weight;
  for (const auto& r : classes) {
    if (!r.present) continue;
    const double q = 2 * kPi * std::sqrt(double(r.s)) / p.lattice;
    out.peak_q.push_back(q);
    out.peak_s.push_back(r.s);
    // multiplicity |F|^2, Lorentz 1 / q^2 (a powder ring's sphere), Debye-Waller.
    weight.push_back(r.multiplicity * r.intensity / (q * q) *
                     std::exp(-p.debye_waller * p.debye_waller * q * q));
  }
  if (out.peak_q.empty()) throw std::runtime_error("no reflection is present: no powder pattern");
  out.width = p.peak_width > 0 ? p.peak_width : 0.01 * out.peak_q.front();
  const double q_max = out.peak_q.back() + 4 * out.width + 0.05 * out.peak_q.back();
  const int m = std::max(p.samples, 2);
  out.q.resize(m);
  out.intensity.assign(m, 0.0);
  const double sigma = out.width / (2 * std::sqrt(2 * std::log(2.0)));
  const double gamma = out.width / 2;
  for (int i = 0; i < m; ++i) {
    const double q = q_max * i / (m - 1);
    out.q[i] = q;
    double sum = 0;
    for (std::size_t j = 0; j < weight.size(); ++j) {
      const double x = q - out.peak_q[j];
      sum += weight[j] * (p.lorentzian
                              ? gamma / kPi / (x * x + gamma * gamma)
                              : std::exp(-x * x / (2 * sigma * sigma)) /
                                    (sigma * std::sqrt(2 * kPi)));
    }
    out.intensity[i] = sum;
  }
  return out;
}

Indexing index_peaks(const std::vector<double>& peaks, const SpaceGroup& g, int smax,
                     double tol) {
  if (peaks.size() < 2)
    throw std::invalid_argument("indexing needs at least 2 peak positions");
  std::vector<double> q = peaks;
  std::sort(q.begin(), q.end());
  for (std::size_t i = 0; i < q.size(); ++i)
    if (!(q[i] > 0) || !std::isfinite(q[i]) || (i > 0 && q[i] == q[i - 1]))
      throw std::invalid_argument("peak positions must be distinct, finite and > 0");
  std::vector<int> allowed;  // s values with an allowed (h, k, l)
  for (int s = 1; s <= smax; ++s) {
    bool ok = false;
    for (int h = 0; h * h <= s && !ok; ++h)
      for (int k = 0; k <= h && !ok; ++k) {
        const int l2 = s - h * h - k * k;
        const int l = int(std::lround(std::sqrt(double(std::max(l2, 0)))));
        if (l2 >= 0 && l <= k && l * l == l2) ok = space_group_allows(g, h, k, l);
      }
    if (ok) allowed.push_back(s);
  }
  Indexing best;
  best.group = g.symbol;
  bool found = false;
  for (std::size_t first = 0; first < std::min<std::size_t>(allowed.size(), 8); ++first) {
    double u = q[0] / (2 * kPi * std::sqrt(double(allowed[first])));  // 1 / a
    std::vector<int> s(q.size());
    bool assigned = true;
    for (int iter = 0; iter < 4 && assigned; ++iter) {
      std::size_t next = 0;  // assignments strictly increase
      for (std::size_t i = 0; i < q.size() && assigned; ++i) {
        if (next >= allowed.size()) {
          assigned = false;
          break;
        }
        const double want = q[i] / (2 * kPi * u);  // sqrt(s)
        std::size_t at = next;
        while (at + 1 < allowed.size() &&
               std::abs(std::sqrt(double(allowed[at + 1])) - want) <
                   std::abs(std::sqrt(double(allowed[at])) - want))
          ++at;
        s[i] = allowed[at];
        next = at + 1;
      }
      if (!assigned) break;
      double num = 0, den = 0;
      for (std::size_t i = 0; i < q.size(); ++i) {
        const double c = 2 * kPi * std::sqrt(double(s[i]));
        num += q[i] * c, den += c * c;
      }
      u = num / den;
    }
    if (!assigned) continue;
    Indexing fit;
    fit.group = g.symbol;
    fit.lattice = 1 / u;
    fit.s = s;
    double ss = 0, worst = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const double qf = 2 * kPi * std::sqrt(double(s[i])) * u;
      fit.q_fit.push_back(qf);
      fit.residual.push_back((q[i] - qf) / q[i]);
      ss += fit.residual.back() * fit.residual.back();
      worst = std::max(worst, std::abs(fit.residual.back()));
    }
    fit.rms_residual = std::sqrt(ss / double(q.size()));
    if (worst > tol) continue;
    if (!found || fit.lattice < best.lattice * (1 - 1e-9)) best = fit, found = true;
  }
  if (!found)
    throw std::runtime_error(fmt::format(
        "no assignment of the {} peaks to the sqrt(s) that {} allows (s <= {}) fits within a "
        "relative residual of {:g}",
        q.size(), g.symbol, smax, tol));
  return best;
}

ScatteringResult scattering_analysis(const Field& phi, const ScatteringParams& p) {
  ScatteringResult r;
  r.n = phi.n();
  const int max_smax = (r.n / 2 - 1) * (r.n / 2 - 1);
  if (p.smax < 0 || p.smax > max_smax)
    throw std::invalid_argument(fmt::format(
        "smax {} outside [1, {}] on this {}^3 grid (indices up to {}; 0: the default)", p.smax,
        max_smax, r.n, r.n / 2 - 1));
  r.smax = p.smax > 0 ? p.smax : std::min(100, max_smax);
  double lo = INFINITY, hi = -INFINITY;
  for (int k = 0; k < r.n; ++k)
    for (int j = 0; j < r.n; ++j)
      for (int i = 0; i < r.n; ++i)
        lo = std::min(lo, phi(i, j, k)), hi = std::max(hi, phi(i, j, k));
  if (!(lo < 0.5 && hi > 0.5))
    throw std::invalid_argument(
        fmt::format("the field has no phi = 1/2 surface (phi in [{:.6g}, {:.6g}])", lo, hi));
  auto t = WallClock::now();
  const DensityGrid rho = density_from_phase_field(phi, p.density);
  r.interface_width = rho.interface_width;
  r.density_seconds = seconds_since(t);
  t = WallClock::now();
  const StructureFactors f(rho);
  r.fft_seconds = seconds_since(t);
  t = WallClock::now();
  r.f000 = f(0, 0, 0).real();
  r.classes = reflection_classes(f, r.smax, p.absent_tol);
  for (const auto& c : r.classes) r.symmetry_spread = std::max(r.symmetry_spread, c.spread);
  r.space_group = detect_space_group(r.classes);
  r.powder = powder_pattern(r.classes, p.powder);
  if (!p.peaks.empty()) {
    const int d = r.space_group.divisor;
    const int reduced_smax = r.smax / (d * d);
    r.indexing = index_peaks(p.peaks, *r.space_group.best, reduced_smax, p.index_tol);
    r.indexed = true;
    for (const auto& c : r.space_group.consistent) {
      std::optional<Indexing> ix;
      try {
        ix = index_peaks(p.peaks, *c.group, reduced_smax, p.index_tol);
      } catch (const std::runtime_error&) {
      }
      r.by_group.emplace_back(c.group->symbol, ix);
    }
  }
  r.analysis_seconds = seconds_since(t);
  return r;
}

namespace {

nlohmann::json indices(const std::vector<Reflection>& c, bool present) {
  auto list = nlohmann::json::array();
  for (const auto& r : c)
    if (r.present == present) list.push_back({r.h, r.k, r.l});
  return list;
}

nlohmann::json indexing_json(const Indexing& ix, int divisor) {
  return {{"group", ix.group},
          {"lattice_nm", ix.lattice * divisor},
          {"group_cell_nm", ix.lattice},
          {"s", ix.s},
          {"q_fit", ix.q_fit},
          {"relative_residual", ix.residual},
          {"rms_relative_residual", ix.rms_residual}};
}

}  // namespace

nlohmann::json scattering_json(const ScatteringResult& result, const ScatteringParams& p) {
  const SpaceGroupFit& fit = result.space_group;
  nlohmann::json consistent = nlohmann::json::array();
  for (const auto& c : fit.consistent)
    consistent.push_back({{"symbol", c.group->symbol},
                          {"number", c.group->number},
                          {"forbidden_classes", c.forbidden}});
  nlohmann::json accidental = nlohmann::json::array();
  for (const auto& a : fit.accidental) accidental.push_back(a);
  nlohmann::json report = {
      {"grid", result.n},
      {"density", density_model_name(p.density)},
      {"smax", result.smax},
      {"lattice_nm", p.powder.lattice},
      {"debye_waller_nm", p.powder.debye_waller},
      {"peak_width", result.powder.width},
      {"peak_shape", p.powder.lorentzian ? "lorentzian" : "gaussian"},
      {"absent_tol", p.absent_tol},
      {"f000", result.f000},
      {"symmetry_spread", result.symmetry_spread},
      {"space_group",
       {{"symbol", fit.best->symbol},
        {"number", fit.best->number},
        {"same_conditions", fit.best->same_conditions},
        {"cell_divisor", fit.divisor},
        {"consistent", consistent},
        {"accidentally_absent", accidental}}},
      {"allowed", indices(result.classes, true)},
      {"absent", indices(result.classes, false)},
      {"timings", {{"density_seconds", result.density_seconds},
                   {"fft_seconds", result.fft_seconds},
                   {"analysis_seconds", result.analysis_seconds}}}};
  if (p.density.model == DensityModel::kBilayer)
    report["interface_width"] = result.interface_width;
  if (result.indexed) {
    nlohmann::json indexing = indexing_json(result.indexing, fit.divisor);
    indexing["by_group"] = nlohmann::json::object();
    for (const auto& [symbol, ix] : result.by_group)
      indexing["by_group"][symbol] = ix ? indexing_json(*ix, fit.divisor) : nlohmann::json(nullptr);
    report["peaks"] = p.peaks;
    report["indexing"] = indexing;
  }
  return report;
}

}  // namespace cmcsurf
