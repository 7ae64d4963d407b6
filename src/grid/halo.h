// Halo (ghost-layer) exchange plan. Today every copy is a local periodic wrap;
// under MPI the same slabs become packed sends and receives to neighbour ranks,
// so no kernel changes.
#pragma once

#include <memory>
#include <vector>

namespace cmcsurf {

class Field;

// Copy `width` planes normal to `axis`, starting at src_start, into dst_start
// (interior indices, ghosts are negative or >= n). Axes are processed in the
// order they appear; along axes handled earlier the copy spans the ghosts too,
// so edges and corners fill without extra messages.
struct HaloSlab {
  int axis;
  int src_start;
  int dst_start;
  int width;
};

struct HaloPlan {
  int n = 0;
  int ghost = 0;
  std::vector<HaloSlab> slabs;
};

// The periodic wrap of an n^3 block with `ghost` layers: 6 slabs, x then y then z.
std::shared_ptr<const HaloPlan> make_periodic_halo_plan(int n, int ghost);

void apply_halo(const HaloPlan& plan, Field& field);

}  // namespace cmcsurf
