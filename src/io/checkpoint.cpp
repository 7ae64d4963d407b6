#include "io/checkpoint.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include <fmt/format.h>

#include "common/atomic_file.h"
#include "common/input_file.h"
#include "io/run_report.h"
#include "parallel/agree.h"

namespace cmcsurf {

// Field by field, the JSON of the header (nlohmann's macros: a missing key or a wrong type
// throws, which the reader turns into a CheckpointError).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Measures, area, area_error, mean_curvature,
                                   mean_curvature_error, mean_curvature_std, total_mean_curvature,
                                   area_diffuse, mean_curvature_diffuse,
                                   total_mean_curvature_diffuse, mean_curvature_mu,
                                   volume_fraction, volume_fraction_cells, mass, energy, sharp,
                                   euler_characteristic)
// A step of the history: history.csv's columns by name (schema/report_schema.h).
void to_json(nlohmann::json& j, const StepRecord& r) {
  j = nlohmann::json::object();
  for (const HistoryColumnInfo& c : history_column_table())
    std::visit([&](const auto& v) { j[std::string(c.name)] = v; }, history_value(r, c.id));
}
void from_json(const nlohmann::json& j, StepRecord& r) {
  for (const HistoryColumnInfo& c : history_column_table()) {
    // Checkpoints written before the equilibrium residual was recorded lack it (NaN).
    if (c.id == HistoryColumn::kEquilibriumResidual && !j.contains(std::string(c.name))) continue;
    set_history_value(r, c.id, j.at(std::string(c.name)));
  }
}
// The cursor's stage by its name; another name is refused as check_state always did.
void to_json(nlohmann::json& j, RunStage s) { j = std::string(run_stage_name(s)); }
void from_json(const nlohmann::json& j, RunStage& s) {
  const std::string name = j.get<std::string>();
  const std::optional<RunStage> stage = parse_run_stage(name);
  if (!stage)
    throw std::runtime_error(fmt::format("unknown stage '{}' (prerelax, relax or volume)", name));
  s = *stage;
}
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(BisectionResult, beta, v_ave, iterations)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(VolumeIterate, mass, volume_fraction, steps, relaxed)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RunCursor, grid, stage, stage_steps, dt, area, volume,
                                   correction, slope)

namespace {

static_assert(std::endian::native == std::endian::little,
              "checkpoint.bin is little-endian; a big-endian build needs byte swaps");

constexpr std::array<char, 8> kMagic = {'C', 'M', 'C', 'S', 'C', 'K', 'P', 'T'};
constexpr std::array<char, 8> kEndMagic = {'C', 'K', 'P', 'T', 'D', 'O', 'N', 'E'};
constexpr std::size_t kPreambleBytes = 8 + 4 + 4 + 8;
constexpr std::size_t kTrailerBytes = 4 + 8;
constexpr std::uint64_t kMaxHeaderBytes = std::uint64_t(256) << 20;

std::uint32_t crc32_of(std::uint32_t crc, const void* data, std::size_t bytes) {
  return std::uint32_t(::crc32_z(crc, static_cast<const Bytef*>(data), bytes));
}

// Measures' surface topology and curvature integrals, kept apart from the macro above so that
// a checkpoint written before them still reads (a run resumes only with the build that wrote
// it, so such a file is one of the fuzz corpus's seeds, not a run to finish).
nlohmann::json surface_measures_json(const Measures& m) {
  return {{"euler_characteristic_phase2", m.euler_characteristic_phase2},
          {"components_phase1", m.components_phase1},
          {"components_phase2", m.components_phase2},
          {"surface_components", m.surface_components},
          {"gaussian_curvature_integral", m.gaussian_curvature_integral},
          {"willmore_energy", m.willmore_energy},
          {"equilibrium_residual", m.equilibrium_residual}};
}

void surface_measures_from_json(const nlohmann::json& j, Measures& m) {
  j.at("euler_characteristic_phase2").get_to(m.euler_characteristic_phase2);
  j.at("components_phase1").get_to(m.components_phase1);
  j.at("components_phase2").get_to(m.components_phase2);
  j.at("surface_components").get_to(m.surface_components);
  j.at("gaussian_curvature_integral").get_to(m.gaussian_curvature_integral);
  j.at("willmore_energy").get_to(m.willmore_energy);
  m.equilibrium_residual = j.value("equilibrium_residual", 0.0);  // absent before 2026-11-27
}

nlohmann::json result_json(const RunResult& r) {
  nlohmann::json j;
  j["history"] = r.history;
  j["steps"] = r.steps;
  j["volume_steps"] = r.volume_steps;
  j["prerelax_steps"] = r.prerelax_steps;
  j["coarse_steps"] = r.coarse_steps;
  j["vcycles"] = r.vcycles;
  j["unconverged_steps"] = r.unconverged_steps;
  j["converged"] = r.converged;
  j["stop_reason"] = r.stop_reason;
  j["bisection"] = r.bisection ? nlohmann::json(*r.bisection) : nlohmann::json();
  j["mass_before_shift"] = r.mass_before_shift;
  j["volume_constrained"] = r.volume_constrained;
  j["volume_iterates"] = r.volume_iterates;
  j["volume_converged"] = r.volume_converged;
  j["volume_seconds"] = r.volume_seconds;
  j["initial"] = r.initial;
  j["final"] = r.final;
  j["initial_surface"] = surface_measures_json(r.initial);
  j["final_surface"] = surface_measures_json(r.final);
  j["wall_seconds"] = r.wall_seconds;
  j["solver_seconds"] = r.solver_seconds;
  j["measure_seconds"] = r.measure_seconds;
  // Double structures (absent from older files): what a resumed run's warnings compare with,
  // and the volumes --constrain components holds.
  if (const auto& t = r.seed_topology)
    j["seed_topology"] = {t->components_phase1, t->components_phase2,
                          t->euler_characteristic_phase1, t->euler_characteristic_phase2};
  j["component_volume_targets"] = r.component_volume_targets;
  return j;
}

void result_from_json(const nlohmann::json& j, RunResult& r) {
  j.at("history").get_to(r.history);
  j.at("steps").get_to(r.steps);
  j.at("volume_steps").get_to(r.volume_steps);
  j.at("prerelax_steps").get_to(r.prerelax_steps);
  j.at("coarse_steps").get_to(r.coarse_steps);
  j.at("vcycles").get_to(r.vcycles);
  j.at("unconverged_steps").get_to(r.unconverged_steps);
  j.at("converged").get_to(r.converged);
  j.at("stop_reason").get_to(r.stop_reason);
  if (!j.at("bisection").is_null()) r.bisection = j.at("bisection").get<BisectionResult>();
  j.at("mass_before_shift").get_to(r.mass_before_shift);
  j.at("volume_constrained").get_to(r.volume_constrained);
  j.at("volume_iterates").get_to(r.volume_iterates);
  j.at("volume_converged").get_to(r.volume_converged);
  j.at("volume_seconds").get_to(r.volume_seconds);
  j.at("initial").get_to(r.initial);
  j.at("final").get_to(r.final);
  if (j.contains("initial_surface")) surface_measures_from_json(j["initial_surface"], r.initial);
  if (j.contains("final_surface")) surface_measures_from_json(j["final_surface"], r.final);
  j.at("wall_seconds").get_to(r.wall_seconds);
  j.at("solver_seconds").get_to(r.solver_seconds);
  j.at("measure_seconds").get_to(r.measure_seconds);
  if (j.contains("seed_topology") && j["seed_topology"].size() == 4) {
    const auto& t = j["seed_topology"];
    r.seed_topology = PhaseTopology{t[0].get<std::int64_t>(), t[1].get<std::int64_t>(),
                                    t[2].get<std::int64_t>(), t[3].get<std::int64_t>()};
  }
  if (j.contains("component_volume_targets"))
    j["component_volume_targets"].get_to(r.component_volume_targets);
}

// An array a checkpoint holds over phi's block (interior cells, x fastest): a field, or one of
// the Anderson mixer's per-cell arrays (its last correction and F and its differences, in
// float32 as the mixer keeps them).
struct NamedField {
  std::string name;
  const Field* field = nullptr;  // a field, or
  const void* cells = nullptr;   // a mixer array over phi's block
  int bytes = 8;                 // per value: 8 (float64) or 4 (float32)
};

// Calls add(name, array) for each of the mixer's per-cell arrays, in file order: the last
// step's correction and F, then each column's dG and dF, oldest first (named by their ring
// slot).
template <class State, class Add>
void each_mixer_array(State& m, Add&& add) {
  if (m.have_prev) {
    add(std::string("anderson_prev_c"), m.prev_c);
    add(std::string("anderson_prev_f"), m.prev_f);
  }
  for (const int s : m.column_slots()) {
    add(fmt::format("anderson_dg{}", s), m.dg[std::size_t(s)]);
    add(fmt::format("anderson_df{}", s), m.df[std::size_t(s)]);
  }
}

// The arrays a checkpoint holds, in file order: phi always, the stepper's fields when valid,
// the mixer's arrays when it carries a mixer.
std::vector<NamedField> fields_of(const Checkpoint& c) {
  std::vector<NamedField> f = {{"phi", &c.result.phi}};
  if (c.stepper.nu_valid) f.push_back({"nu", &c.stepper.nu});
  if (c.stepper.history_valid) {
    f.push_back({"prev_phi", &c.stepper.prev_phi});
    f.push_back({"prev_nu", &c.stepper.prev_nu});
  }
  if (c.anderson)
    each_mixer_array(*c.anderson, [&](const std::string& name, const auto& v) {
      f.push_back({name, nullptr, v.data(), int(sizeof v[0])});
    });
  return f;
}

// The mixer's counts and small arrays in the header (its per-cell arrays are rows).
nlohmann::json mixer_json(const std::optional<AndersonState>& m) {
  if (!m) return nullptr;
  return {{"depth", m->depth},       {"columns", m->columns}, {"newest", m->newest},
          {"have_prev", m->have_prev}, {"gram", m->gram},     {"dg_mean", m->dg_mean},
          {"prev_c_mean", m->prev_c_mean}, {"last_residual", m->last_residual}};
}

std::optional<AndersonState> mixer_from_json(const nlohmann::json& j) {
  if (j.is_null()) return std::nullopt;
  AndersonState m;
  j.at("depth").get_to(m.depth);
  j.at("columns").get_to(m.columns);
  j.at("newest").get_to(m.newest);
  j.at("have_prev").get_to(m.have_prev);
  j.at("gram").get_to(m.gram);
  j.at("dg_mean").get_to(m.dg_mean);
  // Files whose mixer kept G in float64 lack it; their arrays' names are refused below.
  m.prev_c_mean = j.value("prev_c_mean", 0.0);
  j.at("last_residual").get_to(m.last_residual);
  return m;
}

// Where an array read from a file goes: a field, or a mixer array sized to the block.
struct ReadTarget {
  std::string name;
  int bytes = 8;
  Field* field = nullptr;
  void* cells = nullptr;
};

// The index of the first non-finite value of a row of `len` values of `bytes` each, or -1.
int first_non_finite(const unsigned char* row, int len, int bytes) {
  for (int i = 0; i < len; ++i) {
    const unsigned char* at = row + std::size_t(i) * std::size_t(bytes);
    bool finite;
    if (bytes == 8) {
      double v;
      std::memcpy(&v, at, sizeof v);
      finite = std::isfinite(v);
    } else {
      float v;
      std::memcpy(&v, at, sizeof v);
      finite = std::isfinite(v);
    }
    if (!finite) return i;
  }
  return -1;
}

template <class T>
void put(std::ostream& out, const T& v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof v);
}

// Bytes to parse: a file read in pieces or a span in memory, behind one interface.
class Source {
 public:
  virtual ~Source() = default;
  virtual std::uint64_t size() const = 0;
  // Reads exactly `bytes` or throws (the caller has checked the size).
  virtual void read(void* to, std::size_t bytes) = 0;
};

class SpanSource final : public Source {
 public:
  explicit SpanSource(std::span<const unsigned char> b) : bytes_(b) {}
  std::uint64_t size() const override { return bytes_.size(); }
  void read(void* to, std::size_t n) override {
    if (n == 0) return;  // memcpy from or to a null pointer is undefined even for 0 bytes
    if (n > bytes_.size() - pos_) throw std::runtime_error("read past the end");
    std::memcpy(to, bytes_.data() + pos_, n);
    pos_ += n;
  }

 private:
  std::span<const unsigned char> bytes_;
  std::size_t pos_ = 0;
};

class FileSource final : public Source {
 public:
  explicit FileSource(const std::filesystem::path& path) : in_(open(path)) {
    if (!in_) throw CheckpointError(fmt::format("{}: cannot open", path.string()));
    std::error_code ec;
    size_ = std::filesystem::file_size(path, ec);
    if (ec) throw CheckpointError(fmt::format("{}: {}", path.string(), ec.message()));
  }
  std::uint64_t size() const override { return size_; }
  static std::ifstream open(const std::filesystem::path& path) {
    try {
      require_regular_file(path, "checkpoint");  // before the open: a FIFO would block it
    } catch (const std::runtime_error& e) {
      throw CheckpointError(e.what());
    }
    return std::ifstream(path, std::ios::binary);
  }
  void read(void* to, std::size_t n) override {
    if (!in_.read(static_cast<char*>(to), std::streamsize(n)))
      throw std::runtime_error("read error (the file changed while being read?)");
  }

 private:
  std::ifstream in_;
  std::uint64_t size_ = 0;
};

template <class T>
T get(Source& in) {
  T v;
  in.read(&v, sizeof v);
  return v;
}

void check_state(const CheckpointFile& f, int max_n) {
  const Checkpoint& c = f.checkpoint;
  const RunCursor& k = c.cursor;
  auto fail = [](const std::string& what) { throw std::runtime_error(what); };
  if (k.grid < 2 || k.grid > max_n)
    fail(fmt::format("grid {} outside [2, {}]", k.grid, max_n));
  // The parameters pass the command line's checks; the stage's grid is N / 2^k of the run's.
  const RunParams p = params_from_json(f.params);
  bool on_a_level = false;
  for (int levels = 0; levels <= p.coarse_levels; ++levels)
    on_a_level = on_a_level || k.grid == p.grid >> levels;
  if (!on_a_level)
    fail(fmt::format("stage grid {} is not the run's grid {} or one of its {} coarse level(s)",
                     k.grid, p.grid, p.coarse_levels));
  if (!f.outputs.is_object()) fail("'outputs' is not an object");
  if (!(std::isfinite(k.dt) && k.dt > 0.0)) fail(fmt::format("time step {} not positive", k.dt));
  if (k.stage_steps < 0 || k.correction < 0 || c.step < 0)
    fail("negative step or correction count");
  if (!std::isfinite(k.area) || !std::isfinite(k.volume) || !std::isfinite(k.slope) ||
      !std::isfinite(c.time) || !(std::isfinite(c.elapsed) && c.elapsed >= 0.0 && c.elapsed <= 1e9))
    fail("non-finite position, or elapsed seconds outside [0, 1e9]");
  if (c.stepper.history_valid && !(std::isfinite(c.stepper.prev_dt) && c.stepper.prev_dt > 0.0))
    fail("the stepper's previous time step is not positive");
  if (!c.result.history.empty() && c.result.history.back().step != c.step)
    fail(fmt::format("history ends at step {} but the checkpoint is at step {}",
                     c.result.history.back().step, c.step));
}

// ---- formats 5 and 7: the fields in one piece file per process -----------------

constexpr std::array<char, 8> kPieceMagic = {'C', 'M', 'C', 'S', 'C', 'P', 'R', 'T'};
constexpr std::size_t kPiecePreambleBytes = 8 + 4 + 8 + 4 + 3 * 4 + 3 * 4 + 4;
constexpr std::size_t kMaxPieces = std::size_t(1) << 20;

struct PieceEntry {
  std::string file;  // in checkpoint.parts/
  std::array<int, 3> offset{}, size{};
  std::uint32_t crc = 0;
};

struct PieceList {
  std::uint64_t id = 0;
  std::vector<PieceEntry> pieces;  // in rank order
};

std::string piece_file_name(std::uint64_t id, std::size_t rank) {
  return fmt::format("{:016x}-r{:06d}.bin", id, rank);
}

nlohmann::json piece_list_json(const PieceList& list) {
  nlohmann::json entries = nlohmann::json::array();
  for (const PieceEntry& p : list.pieces)
    entries.push_back({{"file", p.file}, {"offset", p.offset}, {"size", p.size}, {"crc", p.crc}});
  return {{"id", fmt::format("{:016x}", list.id)}, {"list", entries}};
}

// The header's pieces: an id of 16 hex digits, and 1 to kMaxPieces entries named after it and
// their rank (so that no name leaves the pieces' folder). Throws on anything else.
PieceList read_piece_list(const nlohmann::json& j) {
  PieceList list;
  const std::string id = j.at("id").get<std::string>();
  if (id.size() != 16 || id.find_first_not_of("0123456789abcdef") != std::string::npos)
    throw std::runtime_error(fmt::format("pieces.id '{}' is not 16 hex digits", id));
  list.id = std::stoull(id, nullptr, 16);
  const nlohmann::json& entries = j.at("list");
  if (!entries.is_array() || entries.empty() || entries.size() > kMaxPieces)
    throw std::runtime_error(fmt::format("pieces.list holds {} entries; 1 to {} expected",
                                         entries.is_array() ? entries.size() : 0, kMaxPieces));
  for (std::size_t q = 0; q < entries.size(); ++q) {
    const nlohmann::json& e = entries[q];
    PieceEntry p;
    e.at("file").get_to(p.file);
    e.at("offset").get_to(p.offset);
    e.at("size").get_to(p.size);
    const nlohmann::json& crc = e.at("crc");
    if (!crc.is_number_unsigned() || crc.get<std::uint64_t>() > 0xffffffffULL)
      throw std::runtime_error(fmt::format("piece {} has a CRC-32 of {}", q, crc.dump()));
    p.crc = std::uint32_t(crc.get<std::uint64_t>());
    if (p.file != piece_file_name(list.id, q))
      throw std::runtime_error(fmt::format("piece {} is named '{}'; expected '{}'", q, p.file,
                                           piece_file_name(list.id, q)));
    list.pieces.push_back(std::move(p));
  }
  return list;
}

// The pieces' boxes form a Cartesian grid that tiles the n^3 grid: along each axis their
// bounds cut [0, n) into intervals, each piece is one interval per axis, and every
// combination of intervals is exactly one piece.
template <class Error>
void check_tiling(const PieceList& list, int n, const Error& error) {
  std::array<std::vector<int>, 3> cuts;
  for (std::size_t q = 0; q < list.pieces.size(); ++q) {
    const PieceEntry& p = list.pieces[q];
    for (int a = 0; a < 3; ++a) {
      if (p.offset[a] < 0 || p.size[a] < 1 || p.offset[a] > n - p.size[a])
        throw error(fmt::format("piece {} (offset {} {} {}, size {} {} {}) is not inside the "
                                "{}^3 grid",
                                q, p.offset[0], p.offset[1], p.offset[2], p.size[0], p.size[1],
                                p.size[2], n));
      cuts[a].push_back(p.offset[a]);
      cuts[a].push_back(p.offset[a] + p.size[a]);
    }
  }
  std::size_t cells = 1;
  for (auto& c : cuts) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    cells *= c.size() - 1;
  }
  std::vector<std::array<std::size_t, 3>> at;
  for (std::size_t q = 0; q < list.pieces.size(); ++q) {
    const PieceEntry& p = list.pieces[q];
    std::array<std::size_t, 3> index{};
    for (int a = 0; a < 3; ++a) {
      const auto& c = cuts[a];
      const std::size_t lo =
          std::size_t(std::lower_bound(c.begin(), c.end(), p.offset[a]) - c.begin());
      if (lo + 1 >= c.size() || c[lo + 1] != p.offset[a] + p.size[a])
        throw error(fmt::format("piece {} spans more than one of the pieces' intervals along "
                                "axis {}; the pieces do not form a grid of boxes",
                                q, a));
      index[a] = lo;
    }
    at.push_back(index);
  }
  std::sort(at.begin(), at.end());
  const bool repeated = std::adjacent_find(at.begin(), at.end()) != at.end();
  if (cuts[0].front() != 0 || cuts[1].front() != 0 || cuts[2].front() != 0 || cuts[0].back() != n ||
      cuts[1].back() != n || cuts[2].back() != n || repeated || at.size() != cells)
    throw error(fmt::format("the {} pieces do not tile the {}^3 grid (a box missing or held "
                            "twice)",
                            list.pieces.size(), n));
}

// Keeps the values of global row (j, k), cells x0 .. x0+len-1, that the block holds (the
// block of the target's field, or of `block` for a mixer array).
void keep_row(const ReadTarget& t, const Field& block, const unsigned char* row, int x0, int j,
              int k, int len) {
  const auto& o = block.offset();
  const int lj = j - o[1], lk = k - o[2];
  if (lj < 0 || lj >= block.ny() || lk < 0 || lk >= block.nz()) return;
  const int i0 = std::max(x0, o[0]), i1 = std::min(x0 + len, o[0] + block.nx());
  if (i1 <= i0) return;
  const std::size_t b = std::size_t(t.bytes);
  unsigned char* to =
      t.field ? reinterpret_cast<unsigned char*>(&(*t.field)(i0 - o[0], lj, lk))
              : static_cast<unsigned char*>(t.cells) +
                    ((std::size_t(lk) * std::size_t(block.ny()) + std::size_t(lj)) *
                         std::size_t(block.nx()) +
                     std::size_t(i0 - o[0])) *
                        b;
  std::memcpy(to, row + std::size_t(i0 - x0) * b, b * std::size_t(i1 - i0));
}

// Bytes per cell of the arrays, all together.
std::uint64_t bytes_per_cell(const std::vector<ReadTarget>& targets) {
  std::uint64_t b = 0;
  for (const ReadTarget& t : targets) b += std::uint64_t(t.bytes);
  return b;
}

// Reads piece p (file `path`) of the checkpoint `name` (of format `format`) and keeps what the
// block (phi's, the first target's) holds.
void read_piece(const std::filesystem::path& path, const PieceEntry& p, std::uint32_t format_want,
                std::uint64_t id, int n, const std::vector<ReadTarget>& targets,
                const std::string& name) {
  auto error = [&](const std::string& what) {
    return CheckpointError(fmt::format("{}: piece '{}': {}", name, path.string(), what));
  };
  std::unique_ptr<FileSource> in;
  try {
    in = std::make_unique<FileSource>(path);
  } catch (const std::exception&) {
    throw error("missing or unreadable");
  }
  const std::uint64_t cells = std::uint64_t(p.size[0]) * p.size[1] * p.size[2];
  const std::uint64_t want =
      kPiecePreambleBytes + cells * bytes_per_cell(targets) + kTrailerBytes;
  if (in->size() != want)
    throw error(fmt::format("{} bytes, but the header describes {} (truncated or padded)",
                            in->size(), want));
  std::array<unsigned char, kPiecePreambleBytes> pre{};
  in->read(pre.data(), pre.size());
  std::uint32_t crc = crc32_of(0, pre.data(), pre.size());
  std::array<char, 8> magic{};
  std::uint32_t format = 0, count = 0;
  std::uint64_t piece_id = 0;
  std::int32_t piece_n = 0;
  std::array<std::int32_t, 3> offset{}, size{};
  const unsigned char* q = pre.data();
  auto take = [&](void* to, std::size_t bytes) {
    std::memcpy(to, q, bytes);
    q += bytes;
  };
  take(magic.data(), 8);
  take(&format, 4);
  take(&piece_id, 8);
  take(&piece_n, 4);
  take(offset.data(), 12);
  take(size.data(), 12);
  take(&count, 4);
  if (magic != kPieceMagic) throw error("not a cmcsurf checkpoint piece (no CMCSCPRT signature)");
  if (format != format_want || piece_id != id)
    throw error(fmt::format("it belongs to another checkpoint (format {}, id {:016x}; the header "
                            "wants format {}, id {:016x})",
                            format, piece_id, format_want, id));
  if (piece_n != n || offset != p.offset || size != p.size || count != targets.size())
    throw error(fmt::format(
        "it holds {} field(s) on offset {} {} {}, size {} {} {} of a {}^3 grid; "
        "the header wants {} on offset {} {} {}, size {} {} {} of {}^3",
        count, offset[0], offset[1], offset[2], size[0], size[1], size[2], piece_n, targets.size(),
        p.offset[0], p.offset[1], p.offset[2], p.size[0], p.size[1], p.size[2], n));
  std::vector<unsigned char> row(std::size_t(p.size[0]) * sizeof(double));
  for (const ReadTarget& t : targets) {
    const std::size_t row_bytes = std::size_t(p.size[0]) * std::size_t(t.bytes);
    for (int k = 0; k < p.size[2]; ++k)
      for (int j = 0; j < p.size[1]; ++j) {
        in->read(row.data(), row_bytes);
        crc = crc32_of(crc, row.data(), row_bytes);
        const int i = first_non_finite(row.data(), p.size[0], t.bytes);
        if (i >= 0)
          throw error(fmt::format("field '{}' holds a non-finite value at cell ({}, {}, {})",
                                  t.name, p.offset[0] + i, p.offset[1] + j, p.offset[2] + k));
        keep_row(t, *targets[0].field, row.data(), p.offset[0], p.offset[1] + j,
                 p.offset[2] + k, p.size[0]);
      }
  }
  const auto piece_crc = get<std::uint32_t>(*in);
  std::array<char, 8> end{};
  in->read(end.data(), end.size());
  if (piece_crc != crc || end != kEndMagic)
    throw error("its checksum does not match (the piece is corrupted)");
  if (crc != p.crc)
    throw error(fmt::format("its checksum {:08x} is not the {:08x} the header records (a piece "
                            "of another checkpoint)",
                            crc, p.crc));
}

// `file`: the checkpoint's path (its pieces lie beside it), null for bytes in memory.
CheckpointFile parse(Source& in, const CheckpointReadOptions& options, const std::string& name,
                     const std::filesystem::path* file) {
  auto error = [&](const std::string& what) {
    return CheckpointError(fmt::format("{}: {}", name, what));
  };
  const std::uint64_t size = in.size();
  if (size < kPreambleBytes + kTrailerBytes)
    throw error(fmt::format("{} bytes: too short for a checkpoint (truncated?)", size));
  std::array<char, 8> magic{};
  in.read(magic.data(), magic.size());
  if (magic != kMagic) throw error("not a cmcsurf checkpoint (no CMCSCKPT signature)");
  const auto format = get<std::uint32_t>(in);
  if (format < std::uint32_t(kCheckpointFormatNoMixer) ||
      format > std::uint32_t(kCheckpointPiecesFormat))
    throw error(fmt::format("checkpoint format {}; this cmcsurf reads formats {} to {}", format,
                            kCheckpointFormatNoMixer, kCheckpointPiecesFormat));
  const bool pieces = format == std::uint32_t(kCheckpointPiecesFormat) ||
                      format == std::uint32_t(kCheckpointPiecesFormatNoMixer);
  const bool mixer = format >= std::uint32_t(kCheckpointFormat);
  if (pieces && !file)
    throw error(fmt::format("a checkpoint in pieces (format {}) is read from its folder, not "
                            "from memory",
                            format));
  const auto header_crc = get<std::uint32_t>(in);
  const auto header_bytes = get<std::uint64_t>(in);
  if (header_bytes == 0) throw error("empty header");
  if (header_bytes > kMaxHeaderBytes || header_bytes > size - kPreambleBytes - kTrailerBytes)
    throw error(fmt::format("header of {} bytes does not fit the file's {} bytes (truncated?)",
                            header_bytes, size));
  std::vector<std::uint8_t> header(header_bytes);
  in.read(header.data(), header.size());
  if (crc32_of(0, header.data(), header.size()) != header_crc)
    throw error("the header's checksum does not match (the file is corrupted)");

  CheckpointFile f;
  struct ListedField {
    std::string name;
    long long n = 0;
    int bytes = 8;
  };
  std::vector<ListedField> fields;
  PieceList piece_list;
  try {
    const nlohmann::json h = nlohmann::json::from_cbor(header);
    h.at("version").get_to(f.version);
    h.at("build").get_to(f.build);
    f.params = h.at("params");
    f.outputs = h.at("outputs");
    Checkpoint& c = f.checkpoint;
    h.at("cursor").get_to(c.cursor);
    const nlohmann::json& s = h.at("state");
    s.at("step").get_to(c.step);
    s.at("time").get_to(c.time);
    s.at("last_step_converged").get_to(c.last_step_converged);
    s.at("elapsed").get_to(c.elapsed);
    const nlohmann::json& st = h.at("stepper");
    st.at("nu_valid").get_to(c.stepper.nu_valid);
    st.at("history_valid").get_to(c.stepper.history_valid);
    st.at("prev_dt").get_to(c.stepper.prev_dt);
    result_from_json(h.at("result"), c.result);
    // Formats 6 and 7 carry the mixer (null: none) and each array's bytes per value.
    c.anderson_carried = mixer;
    if (mixer) c.anderson = mixer_from_json(h.at("anderson"));
    for (const nlohmann::json& fj : h.at("fields"))
      fields.push_back({fj.at("name").get<std::string>(), fj.at("n").get<long long>(),
                        mixer ? fj.at("bytes").get<int>() : 8});
    if (pieces) piece_list = read_piece_list(h.at("pieces"));
  } catch (const std::exception& e) {  // nlohmann's parse, type and key errors
    throw error(fmt::format("the header is not a valid checkpoint header: {}", e.what()));
  }
  if (!options.require_version.empty() && f.version != options.require_version)
    throw error(fmt::format("written by cmcsurf {}, this is {}: a run resumes only with the "
                            "version that started it (another build may take other V-cycles)",
                            f.version, options.require_version));
  if (!options.require_build.empty() && f.build != options.require_build)
    throw error(fmt::format(
        "written by {}; this is {}: a run resumes only with the build that started it (another "
        "compiler, flag or commit may take other V-cycles, so the promise of the same bits "
        "would not hold); finish it with that build, or start the run again",
        f.build, options.require_build));
  try {
    check_state(f, options.max_n);
  } catch (const std::exception& e) {  // params_from_json's and the cursor's checks
    throw error(fmt::format("the header is not a valid checkpoint header: {}", e.what()));
  }

  // The fields the header names must be the ones its stepper flags and mixer imply, all on the
  // cursor's grid, and fill the rest of the file exactly: checked before allocating.
  Checkpoint& c = f.checkpoint;
  const int n = c.cursor.grid;
  if (c.anderson) {
    AndersonState& m = *c.anderson;
    const std::string problem = m.count_problem();
    if (!problem.empty())
      throw error(fmt::format("the header's Anderson mixer is not one a run holds: {}", problem));
    m.dg.resize(std::size_t(m.depth));
    m.df.resize(std::size_t(m.depth));
  }
  std::vector<ReadTarget> expected = {{"phi", 8, &c.result.phi}};
  if (c.stepper.nu_valid) expected.push_back({"nu", 8, &c.stepper.nu});
  if (c.stepper.history_valid) {
    expected.push_back({"prev_phi", 8, &c.stepper.prev_phi});
    expected.push_back({"prev_nu", 8, &c.stepper.prev_nu});
  }
  const std::size_t first_mixer_array = expected.size();
  if (c.anderson)
    each_mixer_array(*c.anderson, [&](const std::string& array, auto& v) {
      expected.push_back({array, int(sizeof v[0]), nullptr, nullptr});
    });
  if (fields.size() != expected.size())
    throw error(fmt::format("{} fields listed, {} expected", fields.size(), expected.size()));
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name != expected[i].name || fields[i].n != n ||
        fields[i].bytes != expected[i].bytes)
      throw error(fmt::format("field {} is '{}' on {}^3 with {} bytes a value; expected '{}' on "
                              "{}^3 with {}",
                              i, fields[i].name, fields[i].n, fields[i].bytes, expected[i].name,
                              n, expected[i].bytes));
  const std::uint64_t cells = std::uint64_t(n) * n * n;
  const std::uint64_t data_bytes = pieces ? 0 : cells * bytes_per_cell(expected);
  const std::uint64_t want = kPreambleBytes + header_bytes + data_bytes + kTrailerBytes;
  if (size != want)
    throw error(fmt::format("{} bytes, but its header describes {} (truncated or padded)", size,
                            want));
  if (pieces) check_tiling(piece_list, n, error);

  // Whole fields, or this process's blocks (left empty where the grid does not split).
  const std::shared_ptr<const Decomposition>& d = options.decomposition;
  const bool split = d && d->distributed();
  if (split && !d->splits(n)) return f;
  for (ReadTarget& t : expected)
    if (t.field) {
      const int ghost = t.name == "phi" ? 2 : 1;
      *t.field = split ? Field(n, ghost, d) : Field(n, ghost);
    }
  const Field& block = c.result.phi;
  if (c.anderson)  // the mixer's arrays over phi's block, in the order of `expected`
    each_mixer_array(*c.anderson,
                     [&, q = first_mixer_array](const std::string&, auto& v) mutable {
                       v.assign(block.interior_size(), 0);
                       expected[q++].cells = v.data();
                     });
  const std::vector<ReadTarget>& targets = expected;
  if (!pieces) {
    // Every row is read (the checksum covers them all); those of the block are kept.
    std::uint32_t crc = 0;
    std::vector<unsigned char> row(std::size_t(n) * sizeof(double));
    for (const ReadTarget& t : targets) {
      const std::size_t row_bytes = std::size_t(n) * std::size_t(t.bytes);
      for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j) {
          in.read(row.data(), row_bytes);
          crc = crc32_of(crc, row.data(), row_bytes);
          const int i = first_non_finite(row.data(), n, t.bytes);
          if (i >= 0)
            throw error(fmt::format("field '{}' holds a non-finite value at cell ({}, {}, {})",
                                    t.name, i, j, k));
          keep_row(t, block, row.data(), 0, j, k, n);
        }
    }
    const auto data_crc = get<std::uint32_t>(in);
    std::array<char, 8> end{};
    in.read(end.data(), end.size());
    if (data_crc != crc || end != kEndMagic)
      throw error("the fields' checksum does not match (the file is corrupted)");
  } else {
    // The trailer of the (field-less) file, then the pieces that overlap this process's block.
    const auto data_crc = get<std::uint32_t>(in);
    std::array<char, 8> end{};
    in.read(end.data(), end.size());
    if (data_crc != 0 || end != kEndMagic)
      throw error("the fields' checksum does not match (the file is corrupted)");
    const std::filesystem::path dir = checkpoint_piece_dir(*file);
    for (std::size_t q = 0; q < piece_list.pieces.size(); ++q) {
      const PieceEntry& p = piece_list.pieces[q];
      bool overlaps = true;
      for (int a = 0; a < 3; ++a)
        overlaps = overlaps && p.offset[a] < block.offset()[a] + block.size()[a] &&
                   block.offset()[a] < p.offset[a] + p.size[a];
      if (overlaps)
        read_piece(dir / p.file, p, format, piece_list.id, n, targets, name);
    }
  }
  if (!split)
    for (const ReadTarget& t : targets)
      if (t.field) t.field->exchange_halo();
  return f;
}

}  // namespace

namespace {

nlohmann::json header_json(const nlohmann::json& params, const Checkpoint& c,
                           const nlohmann::json& outputs, const std::vector<NamedField>& fields) {
  nlohmann::json h;
  h["version"] = CMCSURF_VERSION;
  h["build"] = build_identity();
  h["params"] = params;
  h["outputs"] = outputs;
  h["cursor"] = c.cursor;
  h["state"] = {{"step", c.step},
                {"time", c.time},
                {"last_step_converged", c.last_step_converged},
                {"elapsed", c.elapsed}};
  h["stepper"] = {{"nu_valid", c.stepper.nu_valid},
                  {"history_valid", c.stepper.history_valid},
                  {"prev_dt", c.stepper.prev_dt}};
  h["result"] = result_json(c.result);
  h["anderson"] = mixer_json(c.anderson);
  nlohmann::json list = nlohmann::json::array();
  for (const NamedField& f : fields)
    list.push_back({{"name", f.name}, {"n", c.result.phi.n()}, {"bytes", f.bytes}});
  h["fields"] = list;
  return h;
}

// The arrays' interior rows over the block, x fastest, then y, z, array by array; returns crc
// continued over the bytes written.
std::uint32_t write_field_rows(std::ostream& out, const std::vector<NamedField>& fields,
                               const Field& block, std::uint32_t crc) {
  const int nx = block.nx(), ny = block.ny(), nz = block.nz();
  for (const NamedField& f : fields) {
    const std::size_t row = std::size_t(nx) * std::size_t(f.bytes);
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j) {
        const void* p = f.field ? static_cast<const void*>(&(*f.field)(0, j, k))
                                : static_cast<const unsigned char*>(f.cells) +
                                      (std::size_t(k) * std::size_t(ny) + std::size_t(j)) * row;
        crc = crc32_of(crc, p, row);
        out.write(static_cast<const char*>(p), std::streamsize(row));
      }
  }
  return crc;
}

// The container: preamble, header, the fields' interiors (none for format 7), trailer.
void write_container(const std::filesystem::path& path, int format, const nlohmann::json& h,
                     const std::vector<NamedField>& fields, const Field& block) {
  const std::vector<std::uint8_t> header = nlohmann::json::to_cbor(h);
  AtomicWriter w(path);
  std::ostream& out = w.stream();
  out.write(kMagic.data(), kMagic.size());
  put(out, std::uint32_t(format));
  put(out, crc32_of(0, header.data(), header.size()));
  put(out, std::uint64_t(header.size()));
  out.write(reinterpret_cast<const char*>(header.data()), std::streamsize(header.size()));
  const std::uint32_t crc = write_field_rows(out, fields, block, 0);
  put(out, crc);
  out.write(kEndMagic.data(), kEndMagic.size());
  w.commit();
}

// One process's piece (the layout in checkpoint.h); returns its CRC-32.
std::uint32_t write_piece(const std::filesystem::path& path, std::uint64_t id,
                          const std::vector<NamedField>& fields) {
  const Field& first = *fields[0].field;
  std::array<unsigned char, kPiecePreambleBytes> pre{};
  unsigned char* q = pre.data();
  auto add = [&](const void* from, std::size_t bytes) {
    std::memcpy(q, from, bytes);
    q += bytes;
  };
  const auto format = std::uint32_t(kCheckpointPiecesFormat);
  const auto n = std::int32_t(first.n());
  const auto count = std::uint32_t(fields.size());
  add(kPieceMagic.data(), 8);
  add(&format, 4);
  add(&id, 8);
  add(&n, 4);
  add(first.offset().data(), 12);
  add(first.size().data(), 12);
  add(&count, 4);
  AtomicWriter w(path);
  std::ostream& out = w.stream();
  out.write(reinterpret_cast<const char*>(pre.data()), std::streamsize(pre.size()));
  const std::uint32_t crc =
      write_field_rows(out, fields, first, crc32_of(0, pre.data(), pre.size()));
  put(out, crc);
  out.write(kEndMagic.data(), kEndMagic.size());
  w.commit();
  return crc;
}

// Format 5 (collective over phi's decomposition; one process when phi is whole).
void write_pieces(const std::filesystem::path& path, const nlohmann::json& params,
                  const Checkpoint& c, const nlohmann::json& outputs,
                  const std::vector<NamedField>& fields) {
  const Decomposition* d = c.result.phi.decomposition();
  const int rank = d ? d->rank() : 0, ranks = d ? d->ranks() : 1;
  // A new id for every checkpoint: its pieces never overwrite those the current file names.
  double id_halves[2] = {0.0, 0.0};
  if (rank == 0) {
    std::random_device random;
    const std::uint64_t id =
        ((std::uint64_t(random()) << 32) | random()) ^
        std::uint64_t(std::chrono::steady_clock::now().time_since_epoch().count());
    id_halves[0] = double(id >> 32);
    id_halves[1] = double(id & 0xffffffffULL);
  }
  if (d) d->broadcast(id_halves, 2);
  const std::uint64_t id = (std::uint64_t(id_halves[0]) << 32) | std::uint64_t(id_halves[1]);
  const std::filesystem::path dir = checkpoint_piece_dir(path);
  agree_or_throw(d, rank != 0 ? "" : error_of([&] { ensure_directory(dir); }));

  const std::filesystem::path piece = dir / piece_file_name(id, std::size_t(rank));
  double crc = 0.0;
  std::string error = error_of([&] { crc = double(write_piece(piece, id, fields)); });
  const auto remove_piece = [&] {
    std::error_code ec;
    std::filesystem::remove(piece, ec);  // best effort: a piece no header names
  };
  try {
    agree_or_throw(d, error);
  } catch (...) {
    remove_piece();
    throw;
  }
  std::vector<double> crcs(std::size_t(rank == 0 ? ranks : 1), crc);
  if (d) d->gather(&crc, 1, crcs.data());
  if (rank == 0)
    error = error_of([&] {
      PieceList list;
      list.id = id;
      const int n = c.result.phi.n();
      for (int r = 0; r < ranks; ++r) {
        const Block b = d ? d->block_of(r, n) : Block{n, {n, n, n}, {0, 0, 0}};
        list.pieces.push_back({piece_file_name(id, std::size_t(r)), b.offset, b.size,
                               std::uint32_t(crcs[std::size_t(r)])});
      }
      nlohmann::json h = header_json(params, c, outputs, fields);
      h["pieces"] = piece_list_json(list);
      write_container(path, kCheckpointPiecesFormat, h, {}, c.result.phi);
    });
  try {
    agree_or_throw(d, error);
  } catch (...) {
    remove_piece();
    throw;
  }
  // The new checkpoint is in place: the pieces of the one it replaced go, with any left by a
  // failed or killed write (every writer of this one is done).
  if (rank == 0) {
    const std::string mine = fmt::format("{:016x}-r", id);
    std::error_code ec;
    std::vector<std::filesystem::path> stale;
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
      if (!it->path().filename().string().starts_with(mine)) stale.push_back(it->path());
    for (const auto& p : stale) std::filesystem::remove(p, ec);
  }
}

}  // namespace

std::filesystem::path checkpoint_piece_dir(const std::filesystem::path& path) {
  std::filesystem::path dir = path;
  dir.replace_extension(".parts");
  return dir;
}

void remove_checkpoint(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot remove '{}': {}", path.string(), ec.message()));
  const std::filesystem::path dir = checkpoint_piece_dir(path);
  std::filesystem::remove_all(dir, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot remove '{}': {}", dir.string(), ec.message()));
}

void write_checkpoint(const std::filesystem::path& path, const nlohmann::json& params,
                      const Checkpoint& c, const nlohmann::json& outputs, bool in_pieces) {
  const std::vector<NamedField> fields = fields_of(c);
  const Field& phi = c.result.phi;
  for (const NamedField& f : fields)
    if (f.field && (f.field->n() != c.cursor.grid || f.field->offset() != phi.offset() ||
                    f.field->size() != phi.size()))
      throw std::logic_error(fmt::format("write_checkpoint: field {} is not on phi's block of "
                                         "the {}^3 grid",
                                         f.name, c.cursor.grid));
  if (c.anderson && !c.anderson->problem(phi.interior_size()).empty())
    throw std::logic_error("write_checkpoint: the Anderson mixer's state is not over phi's "
                           "block: " + c.anderson->problem(phi.interior_size()));
  const Decomposition* d = phi.decomposition();
  if ((d && d->distributed()) || in_pieces) {
    write_pieces(path, params, c, outputs, fields);
    return;
  }
  if (!phi.whole())
    throw std::logic_error("write_checkpoint: phi is a block without its decomposition");
  write_container(path, kCheckpointFormat, header_json(params, c, outputs, fields), fields, phi);
}

CheckpointFile read_checkpoint(const std::filesystem::path& path,
                               const CheckpointReadOptions& options) {
  std::unique_ptr<FileSource> in;
  try {
    in = std::make_unique<FileSource>(path);
    return parse(*in, options, path.string(), &path);
  } catch (const CheckpointError&) {
    throw;
  } catch (const std::exception& e) {
    throw CheckpointError(fmt::format("{}: {}", path.string(), e.what()));
  }
}

CheckpointFile parse_checkpoint(std::span<const unsigned char> bytes,
                                const CheckpointReadOptions& options, const std::string& name) {
  SpanSource in(bytes);
  try {
    return parse(in, options, name, nullptr);
  } catch (const CheckpointError&) {
    throw;
  } catch (const std::exception& e) {
    throw CheckpointError(fmt::format("{}: {}", name, e.what()));
  }
}

}  // namespace cmcsurf
