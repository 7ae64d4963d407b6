// Nonlinear FAS multigrid V-cycle (Appendix A), independent of the operator it solves.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

// The unknowns of a system, one Field per component (for Cahn-Hilliard: phi and nu).
using Fields = std::vector<Field>;

// What the cycle needs from a discrete nonlinear operator A (the paper's NSO). Each call works
// on one level; the level's mesh width is 1/u[0].n(). Ghosts (docs/architecture.md): u arrives
// with valid ghosts (the cycle exchanges them after every interior-only update), and smooth()
// returns it with valid ghosts. rhs, out and defects are interior-only fields: their ghosts are
// neither read nor written.
class FasOperator {
 public:
  virtual ~FasOperator() = default;
  virtual int components() const = 0;
  // out = A(u) (interior of out only).
  virtual void apply(const Fields& u, Fields& out) const = 0;
  // out = rhs - A(u) (interior of out only).
  virtual void residual(const Fields& u, const Fields& rhs, Fields& out) const = 0;
  // `sweeps` relaxation sweeps on A(u) = rhs; u's ghosts are valid on return.
  virtual void smooth(Fields& u, const Fields& rhs, int sweeps) const = 0;
  // Norm in which the cycle measures a defect (interior only).
  virtual double norm(const Fields& defect) const = 0;
  // norm(rhs - A(u)); scratch may hold the defect on return. An operator may override it to
  // take the norm without storing the defect (the stop test after every V-cycle needs only
  // the number).
  virtual double residual_norm(const Fields& u, const Fields& rhs, Fields& scratch) const {
    residual(u, rhs, scratch);
    return norm(scratch);
  }
  // coarse = restrict_average(rhs - A(u)) on the next coarser level (interior); scratch may
  // hold the fine defect on return. An operator may fuse the two so that the fine defect is
  // never stored.
  virtual void residual_restricted(const Fields& u, const Fields& rhs, Fields& scratch,
                                   Fields& coarse) const;
};

// Exchanges the halos of every component at once (one message per neighbour under MPI).
void exchange_halos(Fields& u);

struct FasOptions {
  int pre_sweeps = 2;           // beta of Appendix A
  int post_sweeps = 2;
  int coarsest_max_sweeps = 400;  // "solved by smoothing to convergence"
  double coarsest_reduction = 1e-8;
  int coarsest_check_every = 4;
};

// Sizes of the level hierarchy for a finest grid n: n, n/2, ... while the size stays even
// and above 2. Returns an empty vector when n cannot be coarsened at least twice.
std::vector<int> coarsening_sizes(int n);

// Accepted finest sizes: n = m * 2^k with m in {1, 3, 5, 7}, n >= 8; returns "" when n is
// accepted, or a message saying why not and which nearby sizes would be.
std::string check_coarsenable(int n);

struct FasLevel {
  Fields u;        // current approximation (valid ghosts between the cycle's steps)
  Fields rhs;      // right-hand side (source term on the finest level, FAS rhs below); interior
  Fields defect;   // scratch: defect, then A(u_coarse); interior
  Fields u_start;  // restricted approximation before the coarse solve (for the CGC); interior
  // Only on the first level gathered onto every process below a level split among processes:
  // this process's block of the level (restriction target, then correction source).
  Fields block_u, block_v;
};

class FasSolver {
 public:
  // With a decomposition of several processes, the finest level (decomposition->splits(n)) and
  // every coarser level whose blocks still have an even number >= kMinBlockCells of cells per
  // axis are split among the processes; the levels below are gathered onto every process and
  // solved there redundantly (docs/scaling.md).
  FasSolver(int n, int components, int ghost, const FasOptions& options,
            std::shared_ptr<const Decomposition> decomposition = nullptr);

  int levels() const { return int(levels_.size()); }
  int size(int level) const { return levels_[level].u[0].n(); }
  // Whether a level is split among processes (false everywhere on one process).
  bool distributed(int level) const { return levels_[level].u[0].decomposition() != nullptr; }
  // Finest-level unknowns and right-hand side, to be filled by the caller: the interiors only
  // (vcycle() and residual_norm() exchange the halos of solution() first; rhs() is an
  // interior-only field). solution() has valid ghosts after either call.
  Fields& solution() { return levels_[0].u; }
  const Fields& solution() const { return levels_[0].u; }
  Fields& rhs() { return levels_[0].rhs; }
  const FasOptions& options() const { return options_; }

  // One V-cycle on the finest level.
  void vcycle(const FasOperator& op);
  // Norm of rhs - A(u) on the finest level.
  double residual_norm(const FasOperator& op);

 private:
  void cycle(const FasOperator& op, int level);
  void solve_coarsest(const FasOperator& op, int level);

  FasOptions options_;
  std::vector<FasLevel> levels_;
};

}  // namespace cmcsurf
