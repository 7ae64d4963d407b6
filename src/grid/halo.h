// Halo (ghost-layer) exchange plan. Along an axis that one process spans, a slab is a local
// periodic wrap; along an axis split among processes (parallel/decomposition.h) the same slabs
// become packed faces sent to and received from the neighbour ranks, so no kernel changes.
#pragma once

#include <array>
#include <memory>
#include <vector>

namespace cmcsurf {

class Field;
class Decomposition;

// Copy `width` planes normal to `axis`, starting at src_start, into dst_start
// (interior indices, ghosts are negative or >= the block size). Axes are processed in the
// order they appear; along axes handled earlier the copy spans the ghosts too,
// so edges and corners fill without extra messages.
struct HaloSlab {
  int axis;
  int src_start;
  int dst_start;
  int width;
};

struct HaloPlan {
  std::array<int, 3> size{};  // interior cells of the block per axis
  int ghost = 0;
  std::vector<HaloSlab> slabs;  // per axis: low ghosts <- top interior, then high <- bottom
  // Processes sharing the grid; null or a single process: every slab is a local copy.
  std::shared_ptr<const Decomposition> decomposition;
  mutable std::vector<double> buffer;  // packed faces (send lo, send hi, recv lo, recv hi)
};

// The periodic wrap of an n^3 block with `ghost` layers: 6 slabs, x then y then z.
std::shared_ptr<const HaloPlan> make_periodic_halo_plan(int n, int ghost);
// The same for a block of a decomposed grid: local copies along axes with one process,
// neighbour exchanges along the others.
std::shared_ptr<const HaloPlan> make_halo_plan(const std::array<int, 3>& size, int ghost,
                                               std::shared_ptr<const Decomposition> d);

void apply_halo(const HaloPlan& plan, Field& field);
// The same for several fields of one geometry at once: along a split axis one message per
// neighbour carries the faces of all of them.
void apply_halo(const HaloPlan& plan, Field* const* fields, int count);

}  // namespace cmcsurf
