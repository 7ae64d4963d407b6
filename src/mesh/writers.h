// Mesh files: binary STL, binary PLY (indexed), OBJ and 3MF (through lib3mf 1.8, Debian's
// lib3mf-dev: a deflated OPC package with units, one object and its build item, and metadata).
// Each is written to a temporary name and renamed into place.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "mesh/tri_mesh.h"

namespace cmcsurf {

enum class MeshFormat { kStl, kPly, kObj, k3mf };

// "stl", "ply", "obj", "3mf"; anything else throws std::invalid_argument naming them.
MeshFormat parse_mesh_format(const std::string& name);
const char* mesh_format_extension(MeshFormat f);
const char* mesh_format_list();  // "stl|ply|obj|3mf"

// Length units of the coordinates: "um", "mm", "cm", "m", "in"; the 3MF name of each.
bool is_mesh_unit(const std::string& unit);
const char* mesh_units_list();
std::string unit_3mf_name(const std::string& unit);

void write_stl(const std::filesystem::path& path, const TriMesh& mesh);
void write_ply(const std::filesystem::path& path, const TriMesh& mesh);
void write_obj(const std::filesystem::path& path, const TriMesh& mesh);

// What a 3MF file says about its part, under the 3MF core specification's well-known metadata
// names (lib3mf 1.8 drops an unprefixed name it does not know and cannot declare a namespace
// of our own, so the design values go into Description as "key=value; ..."). Empty: left out.
struct MeshMetadata {
  std::string title;        // Title
  std::string description;  // Description
  std::string application = std::string("cmcsurf ") + CMCSURF_VERSION;  // Application
};

// lib3mf 1.8 writes coordinates with 6 decimals in the file's unit (1 nm in mm, 1 um in m).
void write_3mf(const std::filesystem::path& path, const TriMesh& mesh, const std::string& unit,
               const MeshMetadata& meta = {});
void write_mesh(const std::filesystem::path& path, MeshFormat format, const TriMesh& mesh,
                const std::string& unit, const MeshMetadata& meta = {});

// A 3MF file as lib3mf reads it back: the unit, the first mesh object's size, the number of
// build items and the metadata. Throws std::runtime_error with lib3mf's message if it cannot.
struct Read3mf {
  std::string unit;  // "mm", ... (as is_mesh_unit)
  std::size_t vertices = 0, triangles = 0, objects = 0, build_items = 0;
  std::vector<std::pair<std::string, std::string>> metadata;
  TriMesh mesh;  // of the first mesh object
};
Read3mf read_3mf(const std::filesystem::path& path);

}  // namespace cmcsurf
