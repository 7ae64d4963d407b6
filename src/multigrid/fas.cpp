#include "multigrid/fas.h"

#include <fmt/format.h>

#include <stdexcept>

#include "multigrid/transfer.h"

namespace cmcsurf {

std::vector<int> coarsening_sizes(int n) {
  std::vector<int> sizes;
  if (n < 1) return sizes;
  sizes.push_back(n);
  while (n % 2 == 0 && n > 2) {
    n /= 2;
    sizes.push_back(n);
  }
  if (sizes.size() < 3) sizes.clear();
  return sizes;
}

std::string check_coarsenable(int n) {
  int m = n, k = 0;
  while (m > 0 && m % 2 == 0) {
    m /= 2;
    ++k;
  }
  if (n >= 8 && (m == 1 || m == 3 || m == 5 || m == 7) && k >= 2) return "";
  // Suggest the nearest accepted sizes below and above (from the sizes themselves: a search
  // by steps of one overflowed, or took seconds, near the ends of int).
  long long below = 0, above = 0;
  for (const long long odd : {1, 3, 5, 7})
    for (long long c = 4 * odd; c <= (1LL << 34); c *= 2) {
      if (c < 8) continue;
      if (c < n && c > below) below = c;
      if (c > n && (above == 0 || c < above)) above = c;
    }
  std::string near = below >= 8 ? fmt::format("{} or {}", below, above) : fmt::format("{}", above);
  return fmt::format(
      "must be m * 2^k with m in {{1, 3, 5, 7}}, k >= 2 and N >= 8 so that multigrid can "
      "coarsen it; got {} (nearest accepted: {})",
      n, near);
}

FasSolver::FasSolver(int n, int components, int ghost, const FasOptions& options,
                     std::shared_ptr<const Decomposition> decomposition)
    : options_(options) {
  const bool parallel = decomposition && decomposition->distributed();
  if (parallel && !decomposition->splits(n))
    throw std::invalid_argument("FasSolver: " + decomposition->check_grid(n));
  const std::vector<int> sizes = coarsening_sizes(n);
  bool distributed = parallel;
  for (int size : sizes) {
    // HPGMG-style agglomeration: stay split while the blocks are large enough; the coarsest
    // level (odd or 2 cells) is always gathered.
    const bool was_distributed = distributed;
    if (distributed && size != n && (size == sizes.back() || !decomposition->splits(size)))
      distributed = false;
    const auto d = distributed ? decomposition : nullptr;
    FasLevel level;
    for (int c = 0; c < components; ++c) {
      level.u.emplace_back(size, ghost, d);
      level.rhs.emplace_back(size, ghost, d);
      level.defect.emplace_back(size, ghost, d);
      if (size != n) level.u_start.emplace_back(size, ghost, d);
      if (was_distributed && !distributed) {
        level.block_u.emplace_back(size, ghost, decomposition);
        level.block_v.emplace_back(size, ghost, decomposition);
      }
    }
    levels_.push_back(std::move(level));
  }
}

void FasOperator::residual_restricted(const Fields& u, const Fields& rhs, Fields& scratch,
                                      Fields& coarse) const {
  residual(u, rhs, scratch);
  for (std::size_t c = 0; c < scratch.size(); ++c) restrict_average(scratch[c], coarse[c]);
}

void exchange_halos(Fields& u) {
  constexpr std::size_t kMax = 8;
  CMCSURF_CHECK(u.size() <= kMax);
  if (u.empty()) return;
  Field* fields[kMax];
  for (std::size_t c = 0; c < u.size(); ++c) fields[c] = &u[c];
  apply_halo(u[0].halo_plan(), fields, int(u.size()));
}

void FasSolver::vcycle(const FasOperator& op) {
  exchange_halos(levels_[0].u);  // the caller filled the interior
  cycle(op, 0);
}

double FasSolver::residual_norm(const FasOperator& op) {
  FasLevel& fine = levels_[0];
  exchange_halos(fine.u);
  return op.residual_norm(fine.u, fine.rhs, fine.defect);
}

// Steps 1-9 of the FAS cycle in Appendix A. On entry and on return the level's u has valid
// ghosts.
void FasSolver::cycle(const FasOperator& op, int l) {
  for (const Field& f : levels_[l].u) CMCSURF_DCHECK(halo_is_current(f));
  if (l + 1 == levels()) {
    solve_coarsest(op, l);
    return;
  }
  FasLevel& fine = levels_[l];
  FasLevel& coarse = levels_[l + 1];
  const int nc = int(fine.u.size());

  op.smooth(fine.u, fine.rhs, options_.pre_sweeps);  // 1) presmoothing
  const bool gather = !coarse.block_u.empty();  // coarse level held whole by every process
  if (gather) {
    op.residual(fine.u, fine.rhs, fine.defect);  // 2) defect
  } else {  // 2-3) the defect restricted as it is formed
    op.residual_restricted(fine.u, fine.rhs, fine.defect, coarse.rhs);
  }
  for (int c = 0; c < nc; ++c) {  // 3) restrict defect and solution
    if (gather) {
      restrict_average(fine.defect[c], coarse.block_u[c]);
      gather_field(coarse.block_u[c], coarse.rhs[c], true);
      restrict_average(fine.u[c], coarse.block_u[c]);
      gather_field(coarse.block_u[c], coarse.u[c], true);
    } else {
      restrict_average(fine.u[c], coarse.u[c]);
    }
    copy_interior(coarse.u[c], coarse.u_start[c]);
  }
  if (!gather) exchange_halos(coarse.u);  // gather_field exchanged them
  op.apply(coarse.u, coarse.defect);  // 4) coarse rhs = restricted defect + NSO(u_coarse)
  for (int c = 0; c < nc; ++c) {
    Field& rhs = coarse.rhs[c];
    const Field& a = coarse.defect[c];
    const int nx = rhs.nx(), ny = rhs.ny(), nz = rhs.nz();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j) {
        double* r = &rhs(0, j, k);
        const double* av = &a(0, j, k);
        for (int i = 0; i < nx; ++i) r[i] += av[i];
      }
  }
  cycle(op, l + 1);  // 5) coarse solve
  for (int c = 0; c < nc; ++c) {  // 6-8) coarse-grid correction
    if (gather) {
      take_block(coarse.u[c], coarse.block_u[c]);
      take_block(coarse.u_start[c], coarse.block_v[c]);
      add_interpolated_correction(coarse.block_u[c], coarse.block_v[c], fine.u[c]);
    } else {
      add_interpolated_correction(coarse.u[c], coarse.u_start[c], fine.u[c]);
    }
  }
  exchange_halos(fine.u);  // the correction changed the interior only
  op.smooth(fine.u, fine.rhs, options_.post_sweeps);  // 9) postsmoothing
}

void FasSolver::solve_coarsest(const FasOperator& op, int l) {
  FasLevel& level = levels_[l];
  op.residual(level.u, level.rhs, level.defect);
  const double r0 = op.norm(level.defect);
  const int every = std::max(1, options_.coarsest_check_every);
  for (int done = 0; done < options_.coarsest_max_sweeps; done += every) {
    op.smooth(level.u, level.rhs, every);
    op.residual(level.u, level.rhs, level.defect);
    const double r = op.norm(level.defect);
    if (!(r > options_.coarsest_reduction * r0)) break;  // also stops on NaN
  }
}

}  // namespace cmcsurf
