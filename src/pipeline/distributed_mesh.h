// The surface mesh of a decomposed run (`mpirun ... cmcsurf run --mesh FORMAT`) without a
// whole-grid gather: rank 0 runs the serial mesher (mesh/scaffold.h build_surface_scaffold),
// which reads the field one z-plane at a time, and the processes send their part of each
// plane as it is asked for. Rank 0 holds two planes of the field and the mesh (O(N^2)); the
// mesh is the serial run's, vertex for vertex (docs/scaling.md, "Output").
#pragma once

#include "grid/field.h"
#include "mesh/scaffold.h"

namespace cmcsurf {

// Collective over block's decomposition (a whole field: build_scaffold). Rank 0 gets the
// scaffold, the others an empty one. An error on rank 0 (parameters out of range) reaches
// every process: rank 0 throws it, the others throw std::runtime_error saying rank 0 failed.
Scaffold distributed_surface_scaffold(const Field& block, const ScaffoldParams& p);

}  // namespace cmcsurf
