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

#include <filesystem>
#include <map>
#include <span>
#include <string>
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
// Scalars) atomically. Float64 unless float32. Metadata goes into an XML
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

}  // namespace cmcsurf
