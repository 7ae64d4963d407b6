// Anderson acceleration of the time-step map phi^n -> phi^{n+1} at a fixed dt.
//
// Once dt stops growing, the late steps of a relaxation are a fixed-point iteration
// x_{k+1} = G(x_k) whose slowest (geometric) modes decay by only about 0.9 per step. Anderson
// mixing (type II, depth m) replaces G(x_k) by G(x_k) - sum_j gamma_j dG_j, where dG_j and dF_j
// are the differences of the last m values of G and of the residual F = G(x) - x, and gamma
// minimises |F_k - sum_j gamma_j dF_j| (least squares over the grid). Every term is a
// difference of time steps, each of which conserves mass, so the mixed field keeps the mass.
// The translation modes of a periodic surface have F = 0 to first order, so the mixing does
// not move along them.
//
// Every per-cell array is stored in float, and each is a difference formed in double before
// it is rounded, so that it keeps 7 digits of itself, not of phi: the columns dG and dF, the
// last step's F = G - x, and instead of its G the correction c = G - x' that the mix
// subtracted (x' the mixed field, from which the next step starts, so G = x' + c): 8 + 8 m
// bytes per cell. The means of the float roundings of dG and c are taken out of the mixing,
// so that it keeps the mass to round-off, not to the float rounding.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

// Everything a mixer carries from one mix to the next, so that a checkpoint taken between two
// steps continues the mixing to the same bits. The per-cell arrays hold the interior cells of
// the field's block, x fastest.
struct AndersonState {
  int depth = 0;
  int columns = 0;   // valid history columns (<= depth)
  int newest = -1;   // ring slot of the newest column (-1 without columns)
  bool have_prev = false;
  // The last step's correction c = G - x' and F = G - x (empty without have_prev); c is 0
  // where the step was not mixed.
  std::vector<float> prev_c, prev_f;
  double prev_c_mean = 0.0;                // mean of c's float rounding
  std::vector<std::vector<float>> dg, df;  // depth ring slots; only column_slots() are read
  std::vector<double> gram;                // dF_i . dF_j, depth x depth (ring slots)
  std::vector<double> dg_mean;             // mean of each stored dG's float rounding
  double last_residual = 0.0;

  // The ring slots of the valid columns, oldest first.
  std::vector<int> column_slots() const;
  // Why the counts and the small arrays do not describe a mixer's state (empty: they do) ...
  std::string count_problem() const;
  // ... nor the per-cell arrays one over a block of `cells` interior cells.
  std::string problem(std::size_t cells) const;
};

class AndersonMixer {
 public:
  explicit AndersonMixer(int depth);
  // The depth a mixer asked for `depth` columns uses.
  static int effective_depth(int depth);
  int depth() const { return depth_; }
  // Forgets the history (dt changed, a relaxation starts, the last mixing did not pay).
  void reset();
  // x: the field the last step started from, g = G(x): the field it produced (interiors).
  // Between two mixes without a reset, x must be the g the first one left (G is kept as
  // x + c).
  // Replaces the interior of g by the mixed next iterate (the caller exchanges g's halo).
  // Returns the number of history columns used (0: g is left as it was).
  int mix(const Field& x, Field& g);
  // |F_k| of the last mix (root mean square over the cells).
  double last_residual() const { return last_residual_; }
  // Moves the state out (no copy; the mixer is unusable until restore_state) ...
  AndersonState take_state();
  // ... and back, or from a checkpoint (ring slots it lacks are zero: never read). The state
  // must be one of this depth whose problem() is empty.
  void restore_state(AndersonState&& state);

 private:
  int depth_;
  int columns_ = 0;  // valid history columns (<= depth_)
  int newest_ = -1;  // ring index of the newest column
  bool have_prev_ = false;
  std::vector<float> prev_c_, prev_f_;           // c = G - x' and F of the last step
  double prev_c_mean_ = 0.0;                     // mean of prev_c_'s float rounding
  std::vector<std::vector<float>> dg_, df_;      // ring of differences
  std::vector<double> gram_;                     // dF_i . dF_j, depth x depth (ring indices)
  std::vector<double> dg_mean_;                  // mean of each stored dG's float rounding
  double last_residual_ = 0.0;
};

// The same mixing with its history in double (rounded where the mixer stores it in float) and
// written with plain loops (the test twin).
class AndersonMixerRef {
 public:
  explicit AndersonMixerRef(int depth) : depth_(depth) {}
  void reset() { xs_.clear(), gs_.clear(); }
  int mix(const Field& x, Field& g);

 private:
  int depth_;
  std::vector<std::vector<double>> xs_, gs_;  // the last depth + 1 inputs and outputs
};

}  // namespace cmcsurf
