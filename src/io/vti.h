// VTK XML ImageData (.vti) writer and reader for cell-centred scalar fields.
//
// Layout written: WholeExtent "0 N 0 N 0 N", Origin "h/2 h/2 h/2", Spacing "h h h": VTK
// points sit at the cell centres, and the last point on each axis repeats the first (the
// periodic wrap), so ParaView's Contour at 0.5 covers the whole unit cell and copies of the
// file tile seamlessly. The cmcsurf comment says so ("layout=periodic"). Values are PointData
// (x fastest) in a raw <AppendedData> section, each array prefixed by a UInt64 byte count.
// The reader takes both that layout and N^3 points without the wrap (earlier cmcsurf files,
// other writers).
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

inline constexpr const char* kVtiLayoutKey = "layout";
inline constexpr const char* kVtiPeriodicLayout = "periodic";

struct VtiArray {
  std::string name;
  const Field* field;
};

// Writes the arrays (same N, unique non-empty names; the first is the active
// Scalars) atomically. Whole grids give the layout above; blocks of a decomposed grid (all on
// one block, ghost width >= 1, ghosts valid) give one piece of a .pvti (io/pvti.h): the
// block's points "ox ox+nx oy oy+ny oz oz+nz" (WholeExtent = Piece Extent), the last on each
// axis from the high ghosts (the next block's first cells, or the wrap), same Origin and
// Spacing as the whole grid's. Float64 unless float32. Metadata goes into an XML
// comment "<!-- cmcsurf" with one "key=value" line each (backslash escapes for
// '\\', control characters, '=' in keys and "--"), and values that parse as
// finite numbers also become one-tuple Float64 <FieldData> arrays.
void write_vti(const std::filesystem::path& path, const std::vector<VtiArray>& arrays,
               bool float32 = false, const std::map<std::string, std::string>& metadata = {});

struct VtiData {
  int n = 0;
  std::map<std::string, Field> arrays;
  std::map<std::string, std::string> metadata;  // from the cmcsurf comment, if any
};

// Reads raw appended, little-endian, UInt32/UInt64 header, Float32/Float64
// PointData on a cubic extent 0..N-1 (Origin and Spacing are not used: the
// grid is the unit cube). Each Field gets `ghost` layers, filled by
// exchange_halo(). Anything else throws std::runtime_error saying what was
// found and what is supported.
VtiData read_vti(const std::filesystem::path& path, int ghost = 1);

// What a reader accepts, checked before anything is allocated: the header must end (the '_'
// marker of <AppendedData>) within kMaxVtiHeaderBytes; N <= max_n; the arrays' byte ranges may
// not overlap (so what is allocated is bounded by the file's size); every value is finite.
// With `only` set, just that array is read (missing: an error naming the arrays found).
inline constexpr std::size_t kMaxVtiHeaderBytes = std::size_t(1) << 20;
struct VtiReadOptions {
  int ghost = 1;
  int max_n = 1 << 13;
  std::string only;
};
VtiData read_vti(const std::filesystem::path& path, const VtiReadOptions& options);

// The same reader over the bytes of a whole file held in memory (fuzz/vti_fuzz.cpp); `source`
// names them in the messages ("cannot read VTI file '<source>': ...").
VtiData parse_vti(std::span<const unsigned char> bytes, const VtiReadOptions& options = {},
                  const std::string& source = "(memory)");

// ---- Partitioned images (.pvti): io/pvti.h writes and assembles them; the format is here ----

// One piece of a .pvti: its points "x0 x1 y0 y1 z0 z1" (cells x0..x1-1 of the grid and, as the
// last points, the next piece's first ones or the wrap) and its .vti, relative to the .pvti's
// folder.
struct PvtiPiece {
  std::array<long long, 6> extent{};
  std::string source;
};

// The text of a .pvti over pieces of the N^3 grid (WholeExtent "0 N 0 N 0 N", the periodic
// layout and metadata in the cmcsurf comment as write_vti puts them, GhostLevel 0, the
// arrays' names and type as PPointData, one <Piece Extent Source> each).
std::string format_pvti(int n, const std::vector<std::string>& names, bool float32,
                        const std::map<std::string, std::string>& metadata,
                        const std::vector<PvtiPiece>& pieces);

// A .pvti's structure: the file is at most kMaxPvtiBytes with at most kMaxPvtiPieces pieces;
// its root is <VTKFile type="PImageData"> (little-endian, uncompressed) with a cubic
// WholeExtent "0 M 0 M 0 M", GhostLevel 0, PPointData arrays only (scalar Float32/Float64,
// unique names) and pieces with an Extent and a Source. Anything else throws
// std::runtime_error ("cannot read PVTI file '<source>': ..."). The tiling and the piece files
// are checked by read_pvti (io/pvti.h).
inline constexpr std::size_t kMaxPvtiBytes = std::size_t(64) << 20;
inline constexpr std::size_t kMaxPvtiPieces = std::size_t(1) << 20;
struct PvtiHeader {
  std::array<long long, 6> whole_extent{};
  std::vector<std::pair<std::string, bool>> arrays;  // name, float32
  std::vector<PvtiPiece> pieces;
  std::map<std::string, std::string> metadata;  // from the cmcsurf comment, if any
};
PvtiHeader parse_pvti(std::string_view text, const std::string& source);

// Reads one piece file of the .pvti `pvti` (named in the messages): a .vti whose extent must be
// `extent`, holding each target's array with its type. The piece's cells (all points but the
// last on each axis) are checked finite, and those in a target field's block are put there
// (interior only: ghosts are not written). Errors throw std::runtime_error naming the piece.
struct VtiPieceTarget {
  std::string name;
  bool float32 = false;
  Field* field = nullptr;
};
void read_vti_piece(const std::filesystem::path& path, const std::array<long long, 6>& extent,
                    const std::vector<VtiPieceTarget>& targets, const std::string& pvti);

}  // namespace cmcsurf
