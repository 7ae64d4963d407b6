#include "io/pvti.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <regex>
#include <stdexcept>
#include <system_error>

#include <fmt/core.h>

#include "common/atomic_file.h"
#include "common/input_file.h"
#include "parallel/agree.h"

namespace cmcsurf {

namespace fs = std::filesystem;

namespace {

// The cells [lo, hi) per axis that some piece and a box share.
struct Box {
  std::array<long long, 3> lo{}, hi{};
  bool empty() const { return lo[0] >= hi[0] || lo[1] >= hi[1] || lo[2] >= hi[2]; }
};

Box cells_of(const PvtiPiece& p) {
  return {{p.extent[0], p.extent[2], p.extent[4]}, {p.extent[1], p.extent[3], p.extent[5]}};
}

Box intersect(const Box& a, const Box& b) {
  Box c;
  for (int x = 0; x < 3; ++x) {
    c.lo[x] = std::max(a.lo[x], b.lo[x]);
    c.hi[x] = std::min(a.hi[x], b.hi[x]);
  }
  return c;
}

// Which cells of a box the pieces hold so far: one bit per cell, x fastest.
class Coverage {
 public:
  explicit Coverage(const Box& box) : box_(box) {
    for (int a = 0; a < 3; ++a) size_[a] = box.hi[a] - box.lo[a];
    words_per_row_ = (size_[0] + 63) / 64;
    bits_.assign(std::size_t(words_per_row_ * size_[1] * size_[2]), 0);
  }

  // Marks the cells of b (inside the box); false, with the first such cell, if one was marked.
  bool mark(const Box& b, std::array<long long, 3>* twice) {
    const long long x0 = b.lo[0] - box_.lo[0], x1 = b.hi[0] - box_.lo[0];
    for (long long z = b.lo[2]; z < b.hi[2]; ++z)
      for (long long y = b.lo[1]; y < b.hi[1]; ++y) {
        std::uint64_t* row = row_of(y, z);
        for (long long w = x0 / 64; w * 64 < x1; ++w) {
          const std::uint64_t mask = range_mask(w, x0, x1);
          if (row[w] & mask) {
            const long long x = w * 64 + std::countr_zero(row[w] & mask);
            *twice = {box_.lo[0] + x, y, z};
            return false;
          }
          row[w] |= mask;
        }
      }
    return true;
  }

  // The first cell no piece holds, if any.
  bool complete(std::array<long long, 3>* missing) const {
    for (long long z = box_.lo[2]; z < box_.hi[2]; ++z)
      for (long long y = box_.lo[1]; y < box_.hi[1]; ++y) {
        const std::uint64_t* row = bits_.data() + offset_of(y, z);
        for (long long w = 0; w < words_per_row_; ++w) {
          const std::uint64_t gaps = ~row[w] & range_mask(w, 0, size_[0]);
          if (gaps) {
            *missing = {box_.lo[0] + w * 64 + std::countr_zero(gaps), y, z};
            return false;
          }
        }
      }
    return true;
  }

 private:
  std::size_t offset_of(long long y, long long z) const {
    return std::size_t(((z - box_.lo[2]) * size_[1] + (y - box_.lo[1])) * words_per_row_);
  }
  std::uint64_t* row_of(long long y, long long z) { return bits_.data() + offset_of(y, z); }
  // Bits [x0, x1) of word w.
  static std::uint64_t range_mask(long long w, long long x0, long long x1) {
    const long long a = std::max(x0 - w * 64, 0LL), b = std::min(x1 - w * 64, 64LL);
    if (b <= a) return 0;
    const std::uint64_t high = b == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << b) - 1;
    return high & ~((std::uint64_t(1) << a) - 1);
  }

  Box box_;
  std::array<long long, 3> size_{};
  long long words_per_row_ = 0;
  std::vector<std::uint64_t> bits_;
};

struct PvtiFile {
  fs::path path;
  PvtiHeader header;
  int n = 0;
};

[[noreturn]] void fail(const fs::path& path, const std::string& what) {
  throw std::runtime_error(fmt::format("cannot read PVTI file '{}': {}", path.string(), what));
}

// The .pvti's header, its layout and its pieces' extents and sources checked.
PvtiFile open_pvti(const fs::path& path, int max_n) {
  require_regular_file(path, "PVTI file");
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) fail(path, ec.message());
  if (size > kMaxPvtiBytes)
    fail(path, fmt::format("{} bytes; a .pvti of cmcsurf is below {} bytes", size, kMaxPvtiBytes));
  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (!in && !in.eof()) fail(path, "read error");
  PvtiFile f{path, parse_pvti(text, path.string()), 0};
  const auto layout = f.header.metadata.find(kVtiLayoutKey);
  if (layout == f.header.metadata.end() || layout->second != kVtiPeriodicLayout)
    fail(path, fmt::format("{} in a '<!-- cmcsurf' comment; only cmcsurf's periodic layout ({}={}: "
                           "N + 1 points per axis, the last the wrap) is supported",
                           layout == f.header.metadata.end()
                               ? fmt::format("no '{}=' line", kVtiLayoutKey)
                               : fmt::format("{}={}", kVtiLayoutKey, layout->second),
                           kVtiLayoutKey, kVtiPeriodicLayout));
  f.n = int(f.header.whole_extent[1]);
  if (f.n > max_n)
    fail(path, fmt::format("N = {} exceeds the limit {} of this command", f.n, max_n));
  for (std::size_t q = 0; q < f.header.pieces.size(); ++q) {
    const PvtiPiece& p = f.header.pieces[q];
    for (int a = 0; a < 3; ++a)
      if (p.extent[2 * a] < 0 || p.extent[2 * a + 1] > f.n ||
          p.extent[2 * a + 1] <= p.extent[2 * a])
        fail(path, fmt::format("piece {} ('{}') has Extent=\"{} {} {} {} {} {}\"; each piece lies "
                               "inside the WholeExtent \"0 {} 0 {} 0 {}\" with at least one cell "
                               "(two points) per axis",
                               q, p.source, p.extent[0], p.extent[1], p.extent[2], p.extent[3],
                               p.extent[4], p.extent[5], f.n, f.n, f.n));
    const fs::path source(p.source);
    bool escapes = source.is_absolute() || source.has_root_name();
    for (const fs::path& part : source) escapes = escapes || part == "..";
    if (escapes)
      fail(path, fmt::format("piece {} has Source=\"{}\"; a piece lies inside the .pvti's folder "
                             "(a relative path without '..')",
                             q, p.source));
  }
  return f;
}

// The arrays of f that a read wants (all, or `only`), with their types.
std::vector<std::pair<std::string, bool>> wanted_arrays(const PvtiFile& f,
                                                        const std::string& only) {
  if (only.empty()) return f.header.arrays;
  std::string names;
  for (const auto& a : f.header.arrays) {
    if (a.first == only) return {a};
    names += (names.empty() ? "'" : ", '") + a.first + "'";
  }
  fail(f.path, fmt::format("no array '{}' (found {})", only, names));
}

fs::path piece_path(const PvtiFile& f, std::size_t q) {
  const fs::path folder = f.path.has_parent_path() ? f.path.parent_path() : fs::path(".");
  return folder / f.header.pieces[q].source;
}

// Piece q's file is a regular file with at least the bytes its Extent needs for the arrays
// (a byte count and the values of each), from its size alone.
void check_piece_file(const PvtiFile& f, std::size_t q,
                      const std::vector<std::pair<std::string, bool>>& arrays) {
  const PvtiPiece& p = f.header.pieces[q];
  const fs::path piece = piece_path(f, q);
  require_regular_file(piece, fmt::format("piece {} of {}", q, f.path.string()));
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(piece, ec);
  if (ec)
    fail(f.path, fmt::format("piece {} '{}' is missing (no file {})", q, p.source, piece.string()));
  std::uint64_t points = 1;
  for (int a = 0; a < 3; ++a) points *= std::uint64_t(p.extent[2 * a + 1] - p.extent[2 * a] + 1);
  std::uint64_t need = 0;
  for (const auto& [name, float32] : arrays) need += 4 + points * (float32 ? 4 : 8);
  if (size < need)
    fail(f.path, fmt::format("piece {} ('{}') has {} bytes; its Extent \"{} {} {} {} {} {}\" "
                             "needs at least {} for its {} point values",
                             q, p.source, size, p.extent[0], p.extent[1], p.extent[2],
                             p.extent[3], p.extent[4], p.extent[5], need, points));
}

// Before the whole grid is allocated: every piece file holds its Extent's bytes, and the pieces
// hold at least the grid's cells (so what is allocated is bounded by the files' sizes).
void check_piece_files(const PvtiFile& f,
                       const std::vector<std::pair<std::string, bool>>& arrays) {
  std::uint64_t cells = 0;
  for (std::size_t q = 0; q < f.header.pieces.size(); ++q) {
    check_piece_file(f, q, arrays);
    const Box b = cells_of(f.header.pieces[q]);
    cells += std::uint64_t(b.hi[0] - b.lo[0]) * (b.hi[1] - b.lo[1]) * (b.hi[2] - b.lo[2]);
  }
  const std::uint64_t whole = std::uint64_t(f.n) * f.n * f.n;
  if (cells < whole)
    fail(f.path, fmt::format("the pieces hold {} of the grid's {} cells; the pieces must tile "
                             "the grid (a piece missing from the list?)",
                             cells, whole));
}

// Reads the pieces of f that overlap `box` into the fields (all on one block holding `box`),
// after checking that the pieces tile the box exactly.
void read_pieces(const PvtiFile& f, const Box& box,
                 const std::vector<std::pair<std::string, bool>>& arrays,
                 const std::vector<Field*>& fields) {
  const std::vector<PvtiPiece>& pieces = f.header.pieces;
  std::vector<std::size_t> overlapping;
  {
    Coverage coverage(box);
    for (std::size_t q = 0; q < pieces.size(); ++q) {
      const Box common = intersect(cells_of(pieces[q]), box);
      if (common.empty()) continue;
      std::array<long long, 3> cell{};
      if (!coverage.mark(common, &cell))
        fail(f.path, fmt::format("piece {} ('{}') holds cell ({}, {}, {}), which an earlier piece "
                                 "holds too; the pieces must tile the grid",
                                 q, pieces[q].source, cell[0], cell[1], cell[2]));
      overlapping.push_back(q);
    }
    std::array<long long, 3> cell{};
    if (!coverage.complete(&cell))
      fail(f.path, fmt::format("no piece holds cell ({}, {}, {}); the pieces must tile the grid "
                               "(a piece missing from the list?)",
                               cell[0], cell[1], cell[2]));
  }
  std::vector<VtiPieceTarget> targets;
  for (std::size_t a = 0; a < arrays.size(); ++a)
    targets.push_back({arrays[a].first, arrays[a].second, fields[a]});
  for (const std::size_t q : overlapping) {
    check_piece_file(f, q, arrays);
    read_vti_piece(piece_path(f, q), pieces[q].extent, targets, f.path.string());
  }
}

const std::regex& piece_file_pattern() {
  static const std::regex pattern(R"(piece_\d+\.vti(\.cmcsurf-tmp\.\d+\.\d+)?)");
  return pattern;
}

}  // namespace

fs::path pvti_piece_dir(const fs::path& pvti) {
  fs::path dir = pvti;
  dir.replace_extension();
  return dir;
}

std::string pvti_piece_source(const fs::path& pvti, int rank) {
  return fmt::format("{}/piece_{:04d}.vti", pvti.stem().string(), rank);
}

void write_pvti(const fs::path& path, const std::vector<VtiArray>& arrays, bool float32,
                const std::map<std::string, std::string>& metadata) {
  if (arrays.empty() || !arrays[0].field)
    throw std::invalid_argument("write_pvti: no arrays for " + path.string());
  const Field& first = *arrays[0].field;
  const Decomposition* d = first.decomposition();
  const int rank = d ? d->rank() : 0, ranks = d ? d->ranks() : 1;
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const fs::path piece = folder / pvti_piece_source(path, rank);

  // An earlier summary and its pieces go first: from here on no .pvti points at them.
  agree_or_throw(d, rank != 0 ? "" : error_of([&] {
    remove_pvti(path);
    ensure_directory(pvti_piece_dir(path));
  }));
  std::string error = error_of([&] { write_vti(piece, arrays, float32, metadata); });
  const auto remove_piece = [&] {
    std::error_code ec;
    fs::remove(piece, ec);  // best effort: a piece no summary points at
  };
  try {
    agree_or_throw(d, error);
  } catch (...) {
    remove_piece();
    throw;
  }
  // Every piece is in place: the summary.
  if (rank == 0)
    error = error_of([&] {
      std::vector<PvtiPiece> pieces;
      for (int r = 0; r < ranks; ++r) {
        const Block b =
            d ? d->block_of(r, first.n()) : Block{first.n(), first.size(), first.offset()};
        PvtiPiece p;
        for (int a = 0; a < 3; ++a) {
          p.extent[2 * a] = b.offset[a];
          p.extent[2 * a + 1] = b.offset[a] + b.size[a];
        }
        p.source = pvti_piece_source(path, r);
        pieces.push_back(std::move(p));
      }
      std::vector<std::string> names;
      for (const VtiArray& a : arrays) names.push_back(a.name);
      write_file_atomic(path, format_pvti(first.n(), names, float32, metadata, pieces));
    });
  try {
    agree_or_throw(d, error);
  } catch (...) {
    remove_piece();
    throw;
  }
}

void remove_pvti(const fs::path& path) {
  auto remove = [](const fs::path& p) {
    std::error_code ec;
    fs::remove(p, ec);
    if (ec)
      throw std::runtime_error(fmt::format("cannot remove '{}': {}", p.string(), ec.message()));
  };
  remove(path);
  const fs::path dir = pvti_piece_dir(path);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return;
  std::vector<fs::path> pieces;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (std::error_code kind;
        std::regex_match(it->path().filename().string(), piece_file_pattern()) &&
        it->is_regular_file(kind))
      pieces.push_back(it->path());
  if (ec)
    throw std::runtime_error(fmt::format("cannot list '{}': {}", dir.string(), ec.message()));
  for (const fs::path& p : pieces) remove(p);
  if (fs::is_empty(dir, ec) && !ec) fs::remove(dir, ec);
}

VtiData read_pvti(const fs::path& path, const VtiReadOptions& options) {
  const PvtiFile f = open_pvti(path, options.max_n);
  if (options.ghost < 0 || options.ghost > f.n)
    throw std::invalid_argument(
        fmt::format("read_pvti: ghost width {} for N={}", options.ghost, f.n));
  const auto arrays = wanted_arrays(f, options.only);
  check_piece_files(f, arrays);
  const Box whole{{0, 0, 0}, {f.n, f.n, f.n}};
  std::vector<Field> fields;
  std::vector<Field*> targets;
  fields.reserve(arrays.size());
  for (std::size_t a = 0; a < arrays.size(); ++a) {
    fields.emplace_back(f.n, options.ghost);
    targets.push_back(&fields.back());
  }
  read_pieces(f, whole, arrays, targets);
  VtiData result;
  result.n = f.n;
  result.metadata = f.header.metadata;
  for (std::size_t a = 0; a < arrays.size(); ++a) {
    fields[a].exchange_halo();
    result.arrays.emplace(arrays[a].first, std::move(fields[a]));
  }
  return result;
}

void read_pvti_block_interior_only(const fs::path& path, const std::string& name, Field& block) {
  const PvtiFile f = open_pvti(path, std::max(block.n(), 1));
  if (f.n != block.n())
    fail(path, fmt::format("a grid of N = {}; expected N = {}", f.n, block.n()));
  const auto arrays = wanted_arrays(f, name);
  Box box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = block.offset()[a];
    box.hi[a] = block.offset()[a] + block.size()[a];
  }
  read_pieces(f, box, arrays, {&block});
}

fs::path write_run_field(const fs::path& dir, const std::vector<VtiArray>& arrays, bool float32,
                         const std::map<std::string, std::string>& metadata) {
  const Decomposition* d =
      arrays.empty() || !arrays[0].field ? nullptr : arrays[0].field->decomposition();
  if (d && d->distributed()) {
    write_pvti(dir / kRunFieldPvti, arrays, float32, metadata);
    return dir / kRunFieldPvti;
  }
  write_vti(dir / kRunFieldVti, arrays, float32, metadata);
  return dir / kRunFieldVti;
}

void remove_run_field(const fs::path& dir) {
  std::error_code ec;
  fs::remove(dir / kRunFieldVti, ec);
  if (ec)
    throw std::runtime_error(
        fmt::format("cannot remove '{}': {}", (dir / kRunFieldVti).string(), ec.message()));
  remove_pvti(dir / kRunFieldPvti);
}

fs::path run_field_file(const fs::path& dir) {
  const fs::path vti = dir / kRunFieldVti, pvti = dir / kRunFieldPvti;
  const bool has_vti = fs::is_regular_file(vti), has_pvti = fs::is_regular_file(pvti);
  if (has_vti && has_pvti)
    throw std::runtime_error(fmt::format(
        "'{}' holds both {} and {} (one of them left by another run); name the file to read",
        dir.string(), kRunFieldVti, kRunFieldPvti));
  if (!has_vti && !has_pvti)
    throw std::runtime_error(
        fmt::format("'{}' holds no {} or {}", dir.string(), kRunFieldVti, kRunFieldPvti));
  return has_vti ? vti : pvti;
}

VtiData read_field_file(const fs::path& path, const VtiReadOptions& options) {
  if (path.extension() == ".pvti") return read_pvti(path, options);
  return read_vti(path, options);
}

}  // namespace cmcsurf
