// The literature constants a family of CMC surfaces is compared with (docs/families.md), in
// one place: the areas of the P, D and G minimal surfaces per computed cell (the box of the
// nodal formula, a = 1) and the spheres-cylinders-planes profile I_scp of the paper's
// Section 2.3 (Fig. 11). families.png and sweep.json's "literature" read them from here.
#pragma once

#include <optional>
#include <span>
#include <string>

namespace cmcsurf {

struct MinimalSurfaceArea {
  const char* surface;  // P, D, G
  double area;          // per computed cell at alpha = 1/2
  const char* source;
};

// P 2.3451 (Schwarz), D 3.8377 (Schwarz; the Fd-3m box, 8 Pn-3m cells), G 3.0915 (Schoen;
// 3.0919 in some tables).
std::span<const MinimalSurfaceArea> minimal_surface_areas();
// The area of `surface`'s minimal surface, if it is one of them.
std::optional<double> minimal_surface_area(const std::string& surface);

// Section 2.3: the least area of spheres, cylinders and plane pairs in the unit cube enclosing
// volume v in (0, 1/2]: a sphere (36 pi v^2)^(1/3) up to v = 4 pi / 81 (radius 1/3), a
// cylinder 2 sqrt(pi v) up to v = 1 / pi (radius 1/2), a pair of planes 2 beyond. The three
// branches meet where they change (4 pi / 9 and 2).
double i_scp(double v);
// I_scp of the smaller phase, min(alpha, 1 - alpha): a surface enclosing phase 1 of volume
// alpha also encloses phase 0 of volume 1 - alpha.
double i_scp_of_fraction(double alpha);

}  // namespace cmcsurf
