// Writers of periodic tetrahedral meshes (mesh/tet_mesh.h) for finite-element codes, each with
// the periodic node pairs in the form that code reads: gmsh MSH 4.1 ASCII with $Periodic,
// Abaqus .inp with matched node sets for *EQUATION, VTU and XDMF (its heavy data in FILE.h5
// when built with HDF5, else inline XML) with a periodic_master node array. Each file is
// written to a temporary name and renamed.
// How to use the pairs: docs/volume_mesh.md.
#pragma once

#include <filesystem>
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/tet_mesh.h"

namespace cmcsurf {

enum class TetMeshFormat { kMsh, kInp, kVtu, kXdmf };

// "msh|inp|vtu|xdmf"
const char* tet_mesh_format_list();
// `format` ("msh", ...), or from out's extension when empty; throws std::invalid_argument
// naming the accepted values.
TetMeshFormat tet_mesh_format(const std::string& format, const std::filesystem::path& out);
const char* tet_mesh_format_name(TetMeshFormat f);

// Writes the mesh to `path` and `report` (plus file, file_bytes, format, write_seconds,
// version) to path.json, both whole under temporary names before either is renamed. title: a
// line naming the mesh (source, solid), written where the format has a place for it.
void write_tet_mesh_with_report(const TetMesh& m, TetMeshFormat f,
                                const std::filesystem::path& path, const std::string& title,
                                nlohmann::json report);

// Whether .xdmf files get their data in an HDF5 file (libhdf5-dev at configure time), and
// that file's name: FILE.xdmf's stem with .h5.
bool xdmf_hdf5_available();
std::filesystem::path xdmf_heavy_data_path(const std::filesystem::path& xdmf);

// The pairs grouped by translation in whole block periods, as the files list them.
struct PairClass {
  std::array<long, 3> periods{0, 0, 0};
  std::vector<const PeriodicPair*> pairs;
};
std::vector<PairClass> pair_classes(const TetMesh& m);

}  // namespace cmcsurf
