// Fields of a decomposed run in ParaView's partitioned image format, written block by block so
// that no process holds the whole grid (docs/scaling.md, "Output").
//
// Layout, for a summary file DIR/NAME.pvti (a run folder: field.pvti):
//   DIR/NAME.pvti                  PImageData: WholeExtent "0 N 0 N 0 N", Origin h/2, Spacing h,
//                                  GhostLevel 0, PPointData (phi), the cmcsurf comment, and one
//                                  <Piece Extent="x0 x1 y0 y1 z0 z1" Source="NAME/piece_RRRR.vti"/>
//                                  per process, in rank order
//   DIR/NAME/piece_RRRR.vti        process R's block as a .vti of its own (io/vti.h write_vti):
//                                  its cells plus one more point per axis (the next block's first
//                                  cells, or the periodic wrap), so the pieces share their faces
//                                  as VTK's pieces do and together hold exactly field.vti's points
// RRRR is the rank, at least 4 digits. ParaView opens NAME.pvti (XML Partitioned Image Data
// Reader); the pieces alone open too, each in its place in the unit cell.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "grid/field.h"
#include "io/vti.h"

namespace cmcsurf {

inline constexpr const char* kRunFieldVti = "field.vti";
inline constexpr const char* kRunFieldPvti = "field.pvti";

// The folder of a .pvti's pieces ("DIR/NAME" for "DIR/NAME.pvti"), and piece r's Source,
// relative to the .pvti's folder ("NAME/piece_RRRR.vti").
std::filesystem::path pvti_piece_dir(const std::filesystem::path& pvti);
std::string pvti_piece_source(const std::filesystem::path& pvti, int rank);

// Collective over the processes of the arrays' decomposition: every process calls it with its
// blocks (the arrays on one block, ghost width >= 1, ghosts valid; a field that one process
// holds whole gives one piece). In order, each step agreed by all processes before the next:
// rank 0 removes an earlier NAME.pvti and its pieces (remove_pvti) and creates DIR/NAME/;
// every process writes its piece (write_vti: temporary name, fsync, rename); rank 0 writes
// NAME.pvti the same way. A failure on any process makes every process throw
// std::runtime_error with the first failing process's message ("process R of P: ..."), after
// each has removed the piece it wrote; NAME.pvti is then absent, so no summary ever points at
// missing or stale pieces. Float64 unless float32; metadata as write_vti takes it (in the
// .pvti's comment and in every piece).
void write_pvti(const std::filesystem::path& path, const std::vector<VtiArray>& arrays,
                bool float32 = false, const std::map<std::string, std::string>& metadata = {});

// Removes NAME.pvti (first, so that no summary outlives its pieces), then every
// DIR/NAME/piece_*.vti and the temporaries of killed writers there, then DIR/NAME/ if it is
// empty. Missing files are fine; other errors throw std::runtime_error naming the file.
void remove_pvti(const std::filesystem::path& path);

// Reads a .pvti (any number of pieces, any tiling) into whole fields: for a serial tool (mesh
// --from, report), which may hold the whole grid. Checked before anything is allocated: the
// .pvti's structure (io/vti.h parse_pvti), the cmcsurf periodic layout, N <= max_n, every
// piece's Extent inside the WholeExtent with at least one cell per axis, its Source a relative
// path inside the .pvti's folder (no "..", not absolute); then that the pieces' cells tile the
// grid exactly (no cell missing, none in two pieces); then each piece file (its extent equal
// to its Extent, the arrays with the .pvti's types, finite values: io/vti.h read_vti_piece).
// Errors throw std::runtime_error naming the .pvti or the piece. Options as read_vti's (ghost
// width, max_n, only).
VtiData read_pvti(const std::filesystem::path& path, const VtiReadOptions& options = {});

// This process's block of array `name` of a .pvti (block: a Field on the .pvti's grid; only
// the pieces that overlap it are read, with the checks above restricted to it). Interior only:
// block's ghosts are not written; not collective (agree on errors, then exchange the halo).
void read_pvti_block_interior_only(const std::filesystem::path& path, const std::string& name,
                                   Field& block);

// ---- A run folder's field ----

// DIR/field.vti for arrays a process holds whole (write_vti), DIR/field.pvti with its pieces
// for blocks of a decomposed grid (write_pvti, collective). Returns the file written.
std::filesystem::path write_run_field(const std::filesystem::path& dir,
                                      const std::vector<VtiArray>& arrays, bool float32,
                                      const std::map<std::string, std::string>& metadata);
// Removes DIR/field.vti and DIR/field.pvti with its pieces (remove_pvti).
void remove_run_field(const std::filesystem::path& dir);
// The field file of a run folder: DIR/field.vti or DIR/field.pvti. Throws std::runtime_error
// when DIR holds neither, or both (one of them left by another run).
std::filesystem::path run_field_file(const std::filesystem::path& dir);
// read_pvti for a path ending in .pvti, read_vti otherwise.
VtiData read_field_file(const std::filesystem::path& path, const VtiReadOptions& options = {});

}  // namespace cmcsurf
