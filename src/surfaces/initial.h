// Initial phase fields phi^0 on the periodic unit cell (paper Sections 4.1-4.4).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

struct SurfaceInfo {
  std::string name;         // as given to --surface (P, D, G, sphere, cube, noise, ...)
  std::string description;  // one line, with the formula's source
  bool nodal;               // a trigonometric nodal approximation: goes through steps 1-5
  bool balanced;  // both phases congruent, so the 0.5 member is a candidate minimal surface
};

// Every built-in surface, in the order `cmcsurf surfaces` lists them.
const std::vector<SurfaceInfo>& builtin_surfaces();

// Returns nullptr for an unknown name (a user formula "expr:..." is not in the table).
const SurfaceInfo* find_surface(const std::string& name);

struct InitialFieldParams {
  std::string surface = "G";
  double epsilon = 0.01;     // tanh profile width for "sphere"
  double radius = 0.25;      // sphere radius (Section 4.3)
  double noise_mean = 0.5;   // Section 4.1: mean + amplitude * rand(-1, 1)
  double noise_amplitude = 0.01;
  std::uint64_t seed = 1;
};

// True for the nodal surfaces of the table and for user formulas "expr:<formula>".
bool is_nodal_surface(const std::string& name);

// Throws std::invalid_argument (naming the accepted surfaces, or with muParser's message and
// position for a bad "expr:" formula) unless `name` can be passed to make_initial_field.
void validate_surface(const std::string& name);

// Value of the nodal formula at a point of the unit cell (x, y, z in [0, 1)), for nodal
// surfaces only; the formulas are those of Eqs. (7)-(9), including their +0.5 offset.
double nodal_value(const std::string& surface, double x, double y, double z);

// phi^0 sampled at cell centres x_i = (i + 1/2) h; halo is exchanged before returning.
// Throws std::invalid_argument for an unknown surface.
// With a decomposition of several processes, this process's block of that field.
Field make_initial_field(const InitialFieldParams& params, int n, int ghost,
                         std::shared_ptr<const Decomposition> decomposition = nullptr);

}  // namespace cmcsurf
