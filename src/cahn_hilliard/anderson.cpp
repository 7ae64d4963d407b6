#include "cahn_hilliard/anderson.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include <fmt/format.h>

namespace cmcsurf {

namespace {

constexpr int kMaxDepth = 8;
// A residual this many times the last one means the mixing overshot (or the map changed):
// start the history again from this step.
constexpr double kRestartGrowth = 2.0;
// Tikhonov term, relative to the mean diagonal of the normal equations: the columns become
// nearly dependent as the slow modes take over.
constexpr double kRegularization = 1e-10;

// Solves (A + reg I) gamma = b for a small symmetric positive semi-definite A (m x m, row
// major) by Gaussian elimination with partial pivoting; false when it is singular.
bool solve_normal_equations(std::vector<double> a, std::vector<double> b, int m,
                            std::vector<double>& gamma) {
  double trace = 0.0;
  for (int i = 0; i < m; ++i) trace += a[i * m + i];
  if (!(trace > 0.0)) return false;
  for (int i = 0; i < m; ++i) a[i * m + i] += kRegularization * trace / m;
  for (int c = 0; c < m; ++c) {
    int pivot = c;
    for (int r = c + 1; r < m; ++r)
      if (std::abs(a[r * m + c]) > std::abs(a[pivot * m + c])) pivot = r;
    if (a[pivot * m + c] == 0.0) return false;
    if (pivot != c) {
      for (int k = 0; k < m; ++k) std::swap(a[c * m + k], a[pivot * m + k]);
      std::swap(b[c], b[pivot]);
    }
    for (int r = c + 1; r < m; ++r) {
      const double f = a[r * m + c] / a[c * m + c];
      for (int k = c; k < m; ++k) a[r * m + k] -= f * a[c * m + k];
      b[r] -= f * b[c];
    }
  }
  gamma.assign(m, 0.0);
  for (int r = m - 1; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < m; ++k) s -= a[r * m + k] * gamma[k];
    gamma[r] = s / a[r * m + r];
  }
  for (double v : gamma)
    if (!std::isfinite(v)) return false;
  return true;
}

// The mixer's per-cell arrays of one mix: the step's x and G (interiors) and the float
// history, x fastest.
struct MixRows {
  const Field& x;
  Field& g;
  float* prev_c;
  float* prev_f;
  float* dg_new;
  float* df_new;
};

// The mix's first pass with C columns (0: no new difference): F = G - x, the new differences,
// and into sums |F|^2 (0), dF_c . dF_new (1 + c), dF_c . F (1 + kMaxDepth + c) and the sum of
// the new dG's float rounding (last). G_k = x + c_k, so dG = G - G_k = F - c_k. Each row's
// differences are formed in a vectorised loop; the sums then add the cells in order (each
// thread's sums in the cells' order, as one array reduction over the cells did), so that the
// mix has the same bits as that loop.
template <int C>
void mix_sums(const MixRows& a, const float* const* cols, double* sums) {
  constexpr int kSums = 2 * kMaxDepth + 2;
  const int nx = a.g.nx(), ny = a.g.ny(), nz = a.g.nz();
  std::vector<double> fs(std::size_t(nx) * 3);  // a row's F, dF_new and dG rounding
#pragma omp parallel reduction(+ : sums[:kSums]) if (a.g.n() >= kParallelMinN) firstprivate(fs)
  {
    double s_ff = 0.0, s_round = 0.0, s_dd[C + 1] = {}, s_df[C + 1] = {};
    double* f_row = fs.data();
    double* d_row = f_row + nx;
    double* r_row = d_row + nx;
#pragma omp for schedule(static)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j) {
        const double* xr = &a.x(0, j, k);
        const double* gr = &a.g(0, j, k);
        const std::size_t row = (std::size_t(k) * ny + j) * nx;
        float* pc = a.prev_c + row;
        float* pf = a.prev_f + row;
        float* dfn = a.df_new + row;
        float* dgn = a.dg_new + row;
#pragma omp simd
        for (int i = 0; i < nx; ++i) {
          const double f = gr[i] - xr[i];
          f_row[i] = f;
          if constexpr (C > 0) {
            dfn[i] = float(f - double(pf[i]));
            const double dg = f - double(pc[i]);
            dgn[i] = float(dg);
            r_row[i] = double(dgn[i]) - dg;
            d_row[i] = dfn[i];
          }
          pf[i] = float(f);
          pc[i] = 0.0f;  // unless the mix changes g
        }
        for (int i = 0; i < nx; ++i) {
          const double f = f_row[i];
          s_ff += f * f;
          if constexpr (C > 0) {
            s_round += r_row[i];
            const double d = d_row[i];
            for (int c = 0; c < C; ++c) {
              const double col = cols[c][row + i];
              s_dd[c] += col * d;
              s_df[c] += col * f;
            }
          }
        }
      }
    sums[0] += s_ff;
    for (int c = 0; c < C; ++c) {
      sums[1 + c] += s_dd[c];
      sums[1 + kMaxDepth + c] += s_df[c];
    }
    sums[kSums - 1] += s_round;
  }
}

// The mix's second pass with C columns: g -= sum_c gamma_c dG_c - shift, and c = G - x' (the
// correction, in float) into prev_c; returns the sum of c's float rounding, added in the
// cells' order after a vectorised loop over each row, as mix_sums adds.
template <int C>
double mix_apply(const MixRows& a, const float* const* gcols, const double* gamma_in,
                 double shift) {
  const int nx = a.g.nx(), ny = a.g.ny(), nz = a.g.nz();
  double gamma[C];
  for (int c = 0; c < C; ++c) gamma[c] = gamma_in[c];
  std::vector<double> rs(static_cast<std::size_t>(nx));  // a row's rounding of c
  double c_rounding = 0.0;
#pragma omp parallel reduction(+ : c_rounding) if (a.g.n() >= kParallelMinN) firstprivate(rs)
  {
    double sum = 0.0;
    double* r_row = rs.data();
#pragma omp for schedule(static)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j) {
        double* gr = &a.g(0, j, k);
        const std::size_t row = (std::size_t(k) * ny + j) * nx;
        float* pc = a.prev_c + row;
#pragma omp simd
        for (int i = 0; i < nx; ++i) {
          double s = 0.0;
          for (int c = 0; c < C; ++c) s += gamma[c] * double(gcols[c][row + i]);
          const double unmixed = gr[i];
          gr[i] -= s - shift;
          const double correction = unmixed - gr[i];
          pc[i] = float(correction);
          r_row[i] = double(pc[i]) - correction;
        }
        for (int i = 0; i < nx; ++i) sum += r_row[i];
      }
    c_rounding += sum;
  }
  return c_rounding;
}

}  // namespace

std::vector<int> AndersonState::column_slots() const {
  std::vector<int> slots;
  for (int c = columns - 1; c >= 0; --c) slots.push_back((newest - c + depth) % depth);
  return slots;
}

std::string AndersonState::count_problem() const {
  if (depth < 1 || depth > kMaxDepth)
    return fmt::format("depth {} outside [1, {}]", depth, kMaxDepth);
  if (columns < 0 || columns > depth || (columns == 0) != (newest == -1) || newest < -1 ||
      newest >= depth || (columns > 0 && !have_prev))
    return fmt::format("{} column(s), newest in slot {}, {} previous step (depth {})", columns,
                       newest, have_prev ? "a" : "no", depth);
  if (gram.size() != std::size_t(depth) * depth || dg_mean.size() != std::size_t(depth))
    return fmt::format("{} Gram entries and {} means; {} and {} expected", gram.size(),
                       dg_mean.size(), depth * depth, depth);
  for (const std::vector<double>* v : {&gram, &dg_mean})
    for (const double x : *v)
      if (!std::isfinite(x)) return "a non-finite Gram entry or mean";
  if (!(std::isfinite(last_residual) && last_residual >= 0.0))
    return fmt::format("last residual {}", last_residual);
  return {};
}

std::string AndersonState::problem(std::size_t cells) const {
  if (std::string p = count_problem(); !p.empty()) return p;
  const std::size_t want = have_prev ? cells : 0;
  if (prev_c.size() != want || prev_f.size() != want)
    return fmt::format("the last step's correction and F hold {} and {} cells; {} expected",
                       prev_c.size(), prev_f.size(), want);
  if (dg.size() != std::size_t(depth) || df.size() != std::size_t(depth))
    return fmt::format("{} and {} ring slots; {} expected", dg.size(), df.size(), depth);
  for (const int s : column_slots())
    if (dg[s].size() != cells || df[s].size() != cells)
      return fmt::format("column slot {} holds {} and {} cells; {} expected", s, dg[s].size(),
                         df[s].size(), cells);
  return {};
}

int AndersonMixer::effective_depth(int depth) { return std::clamp(depth, 1, kMaxDepth); }

AndersonState AndersonMixer::take_state() {
  AndersonState s;
  s.depth = depth_;
  s.columns = columns_;
  s.newest = newest_;
  s.have_prev = have_prev_;
  if (have_prev_) {
    std::swap(s.prev_c, prev_c_);
    std::swap(s.prev_f, prev_f_);
  }
  s.prev_c_mean = prev_c_mean_;
  std::swap(s.dg, dg_);
  std::swap(s.df, df_);
  s.gram = gram_;
  s.dg_mean = dg_mean_;
  s.last_residual = last_residual_;
  return s;
}

void AndersonMixer::restore_state(AndersonState&& s) {
  CMCSURF_CHECK(s.depth == depth_);
  const std::size_t cells = s.prev_c.size();
  CMCSURF_CHECK(s.problem(cells).empty());
  columns_ = s.columns;
  newest_ = s.newest;
  have_prev_ = s.have_prev;
  prev_c_ = std::move(s.prev_c);
  prev_f_ = std::move(s.prev_f);
  prev_c_mean_ = s.prev_c_mean;
  dg_ = std::move(s.dg);
  df_ = std::move(s.df);
  // A slot outside the columns is written before it is read; mix() expects every slot sized.
  if (have_prev_)
    for (int r = 0; r < depth_; ++r) {
      if (dg_[r].size() != cells) dg_[r].assign(cells, 0.0f);
      if (df_[r].size() != cells) df_[r].assign(cells, 0.0f);
    }
  gram_ = std::move(s.gram);
  dg_mean_ = std::move(s.dg_mean);
  last_residual_ = s.last_residual;
}

AndersonMixer::AndersonMixer(int depth) : depth_(effective_depth(depth)) {
  dg_.resize(depth_);
  df_.resize(depth_);
  gram_.assign(std::size_t(depth_) * depth_, 0.0);
  dg_mean_.assign(depth_, 0.0);
}

void AndersonMixer::reset() {
  columns_ = 0;
  newest_ = -1;
  have_prev_ = false;
}

int AndersonMixer::mix(const Field& x, Field& g) {
  CMCSURF_CHECK(x.size() == g.size());
  const std::size_t cells = g.interior_size();
  if (prev_c_.size() != cells) {
    prev_c_.assign(cells, 0.0f);
    prev_f_.assign(cells, 0.0f);
    for (int s = 0; s < depth_; ++s) {
      dg_[s].assign(cells, 0.0f);
      df_[s].assign(cells, 0.0f);
    }
    reset();
  }
  const bool add_column = have_prev_;
  const int slot = add_column ? (newest_ + 1) % depth_ : 0;
  const int columns = add_column ? std::min(columns_ + 1, depth_) : 0;
  constexpr int kSums = 2 * kMaxDepth + 2;
  constexpr int kDgSum = kSums - 1;
  // Ring slots of the columns after this step's, the new one last.
  int order[kMaxDepth];
  for (int c = 0; c < columns; ++c) order[c] = (slot - columns + 1 + c + depth_) % depth_;

  // One pass: F = G - x, the new differences, |F|^2, dF_j . dF_new, dF_j . F and the sum of
  // the new dG's float rounding (mix_sums).
  double sums[kSums] = {};
  const float* cols[kMaxDepth];
  for (int c = 0; c < columns; ++c) cols[c] = df_[order[c]].data();
  const MixRows rows{x, g, prev_c_.data(), prev_f_.data(), dg_[slot].data(), df_[slot].data()};
  switch (columns) {
    case 0: mix_sums<0>(rows, cols, sums); break;
    case 1: mix_sums<1>(rows, cols, sums); break;
    case 2: mix_sums<2>(rows, cols, sums); break;
    case 3: mix_sums<3>(rows, cols, sums); break;
    case 4: mix_sums<4>(rows, cols, sums); break;
    case 5: mix_sums<5>(rows, cols, sums); break;
    case 6: mix_sums<6>(rows, cols, sums); break;
    case 7: mix_sums<7>(rows, cols, sums); break;
    default: mix_sums<8>(rows, cols, sums); break;
  }
  g.sum_over_ranks(sums, kSums);
  const double residual = std::sqrt(sums[0] / g.global_cells());
  const double previous = last_residual_;
  last_residual_ = residual;
  // The stored dG is F - float(c_k); the true one F - c_k.
  const double c_mean = prev_c_mean_;
  prev_c_mean_ = 0.0;
  const bool had_prev = have_prev_;
  have_prev_ = true;
  if (!add_column) return 0;
  if (had_prev && residual > kRestartGrowth * previous) {  // the mixing did not pay
    columns_ = 0;
    newest_ = -1;
    return 0;
  }
  newest_ = slot;
  columns_ = columns;
  dg_mean_[slot] = sums[kDgSum] / g.global_cells() - c_mean;
  for (int c = 0; c < columns; ++c) {  // the new row and column of the Gram matrix
    gram_[std::size_t(order[c]) * depth_ + slot] = sums[1 + c];
    gram_[std::size_t(slot) * depth_ + order[c]] = sums[1 + c];
  }
  std::vector<double> a(std::size_t(columns) * columns), b(columns), gamma;
  for (int r = 0; r < columns; ++r) {
    b[r] = sums[1 + kMaxDepth + r];
    for (int c = 0; c < columns; ++c)
      a[std::size_t(r) * columns + c] = gram_[std::size_t(order[r]) * depth_ + order[c]];
  }
  if (!solve_normal_equations(a, b, columns, gamma)) return 0;
  const float* gcols[kMaxDepth];
  // The float rounding of the stored dG would move the mean of the mixed field (the mass,
  // which the steps keep) by ~6e-8 of a difference; its mean is taken out again.
  double shift = 0.0;
  for (int c = 0; c < columns; ++c) {
    gcols[c] = dg_[order[c]].data();
    shift += gamma[c] * dg_mean_[order[c]];
  }
  // The mix, and c = G - x' (its float rounding summed) for the next difference.
  double c_rounding = 0.0;
  switch (columns) {
    case 1: c_rounding = mix_apply<1>(rows, gcols, gamma.data(), shift); break;
    case 2: c_rounding = mix_apply<2>(rows, gcols, gamma.data(), shift); break;
    case 3: c_rounding = mix_apply<3>(rows, gcols, gamma.data(), shift); break;
    case 4: c_rounding = mix_apply<4>(rows, gcols, gamma.data(), shift); break;
    case 5: c_rounding = mix_apply<5>(rows, gcols, gamma.data(), shift); break;
    case 6: c_rounding = mix_apply<6>(rows, gcols, gamma.data(), shift); break;
    case 7: c_rounding = mix_apply<7>(rows, gcols, gamma.data(), shift); break;
    default: c_rounding = mix_apply<8>(rows, gcols, gamma.data(), shift); break;
  }
  prev_c_mean_ = g.sum_over_ranks(c_rounding) / g.global_cells();
  return columns;
}

int AndersonMixerRef::mix(const Field& x, Field& g) {
  std::vector<double> xv, gv;
  for_each_cell(g, [&](int i, int j, int k) {
    xv.push_back(x(i, j, k));
    gv.push_back(g(i, j, k));
  });
  const std::size_t cells = gv.size();
  auto residual_of = [&](std::size_t s) {
    double sum = 0.0;
    for (std::size_t c = 0; c < cells; ++c) sum += std::pow(gs_[s][c] - xs_[s][c], 2);
    return std::sqrt(g.sum_over_ranks(sum) / g.global_cells());
  };
  xs_.push_back(xv);
  gs_.push_back(gv);
  const std::size_t last = xs_.size() - 1;
  if (last >= 1 && residual_of(last) > kRestartGrowth * residual_of(last - 1)) {
    xs_.erase(xs_.begin(), xs_.begin() + last);  // keep this step only
    gs_.erase(gs_.begin(), gs_.begin() + last);
    return 0;
  }
  if (int(xs_.size()) > depth_ + 1) {
    xs_.erase(xs_.begin());
    gs_.erase(gs_.begin());
  }
  const int m = int(xs_.size()) - 1;
  if (m == 0) return 0;
  // Columns j = 0..m-1: dF_j = F_{j+1} - F_j and dG_j = G_{j+1} - G_j, each rounded to float
  // as the mixer stores them, from F_j and G_j = x_{j+1} + c_j rounded to float as it keeps
  // them (c_j = G_j - x_{j+1}: the mix's correction, 0 where it did not mix).
  std::vector<std::vector<double>> df(m, std::vector<double>(cells)), dg = df;
  for (int c = 0; c < m; ++c)
    for (std::size_t i = 0; i < cells; ++i) {
      const double f_next = gs_[c + 1][i] - xs_[c + 1][i];
      const double f = float(gs_[c][i] - xs_[c][i]);
      const double correction = float(gs_[c][i] - xs_[c + 1][i]);
      df[c][i] = float(f_next - f);
      dg[c][i] = float(f_next - correction);
    }
  std::vector<double> a(std::size_t(m) * m), b(m), gamma;
  for (int r = 0; r < m; ++r) {
    double s = 0.0;
    for (std::size_t i = 0; i < cells; ++i) s += df[r][i] * (gv[i] - xv[i]);
    b[r] = g.sum_over_ranks(s);
    for (int c = 0; c < m; ++c) {
      double t = 0.0;
      for (std::size_t i = 0; i < cells; ++i) t += df[r][i] * df[c][i];
      a[std::size_t(r) * m + c] = g.sum_over_ranks(t);
    }
  }
  if (!solve_normal_equations(a, b, m, gamma)) return 0;
  double shift = 0.0;  // the mean of the float rounding of the dG, taken out again
  for (int col = 0; col < m; ++col) {
    double sum = 0.0;
    for (std::size_t i = 0; i < cells; ++i) sum += dg[col][i] - (gs_[col + 1][i] - gs_[col][i]);
    shift += gamma[col] * g.sum_over_ranks(sum) / g.global_cells();
  }
  std::size_t c = 0;
  for_each_cell(g, [&](int i, int j, int k) {
    double s = 0.0;
    for (int col = 0; col < m; ++col) s += gamma[col] * dg[col][c];
    g(i, j, k) -= s - shift;
    ++c;
  });
  return m;
}

}  // namespace cmcsurf
