// Mesh files: binary STL, binary PLY (indexed), OBJ and 3MF (a stored zip written here, with
// CRC-32, no compression library). Each is written to a temporary name and renamed into place.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
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
void write_3mf(const std::filesystem::path& path, const TriMesh& mesh, const std::string& unit);
void write_mesh(const std::filesystem::path& path, MeshFormat format, const TriMesh& mesh,
                const std::string& unit);

// CRC-32 (ISO-HDLC, as in zip and PNG) and a stored (method 0) zip archive in memory.
std::uint32_t crc32(std::string_view data, std::uint32_t crc = 0);
struct ZipEntry {
  std::string name;
  std::string data;
};
std::string make_stored_zip(const std::vector<ZipEntry>& entries);

}  // namespace cmcsurf
