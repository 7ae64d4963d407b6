#include "io/checkpoint.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "io/atomic_file.h"
#include "io/run_report.h"

namespace cmcsurf {

// Field by field, the JSON of the header (nlohmann's macros: a missing key or a wrong type
// throws, which the reader turns into a CheckpointError).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Measures, area, area_error, mean_curvature,
                                   mean_curvature_error, mean_curvature_std, total_mean_curvature,
                                   area_diffuse, mean_curvature_diffuse,
                                   total_mean_curvature_diffuse, mean_curvature_mu,
                                   volume_fraction, volume_fraction_cells, mass, energy, sharp,
                                   euler_characteristic)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(StepRecord, step, stage, time, dt, area, d_area, d_phi, energy,
                                   mass, volume_fraction, vcycles, residual, elapsed)
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
  j["wall_seconds"] = r.wall_seconds;
  j["solver_seconds"] = r.solver_seconds;
  j["measure_seconds"] = r.measure_seconds;
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
  j.at("wall_seconds").get_to(r.wall_seconds);
  j.at("solver_seconds").get_to(r.solver_seconds);
  j.at("measure_seconds").get_to(r.measure_seconds);
}

struct NamedField {
  const char* name;
  const Field* field;
};

// The fields a checkpoint holds, in file order: phi always, the stepper's when valid.
std::vector<NamedField> fields_of(const Checkpoint& c) {
  std::vector<NamedField> f = {{"phi", &c.result.phi}};
  if (c.stepper.nu_valid) f.push_back({"nu", &c.stepper.nu});
  if (c.stepper.history_valid) {
    f.push_back({"prev_phi", &c.stepper.prev_phi});
    f.push_back({"prev_nu", &c.stepper.prev_nu});
  }
  return f;
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
  explicit FileSource(const std::filesystem::path& path) : in_(path, std::ios::binary) {
    if (!in_) throw CheckpointError(fmt::format("{}: cannot open", path.string()));
    std::error_code ec;
    size_ = std::filesystem::file_size(path, ec);
    if (ec) throw CheckpointError(fmt::format("{}: {}", path.string(), ec.message()));
  }
  std::uint64_t size() const override { return size_; }
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
  if (k.stage != "prerelax" && k.stage != "relax" && k.stage != "volume")
    fail(fmt::format("unknown stage '{}' (prerelax, relax or volume)", k.stage));
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

CheckpointFile parse(Source& in, const CheckpointReadOptions& options, const std::string& name) {
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
  if (format != std::uint32_t(kCheckpointFormat))
    throw error(fmt::format("checkpoint format {}; this cmcsurf reads format {}", format,
                            kCheckpointFormat));
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
  std::vector<std::pair<std::string, long long>> fields;
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
    for (const nlohmann::json& fj : h.at("fields"))
      fields.emplace_back(fj.at("name").get<std::string>(), fj.at("n").get<long long>());
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

  // The fields the header names must be the ones its stepper flags imply, all on the
  // cursor's grid, and fill the rest of the file exactly: checked before allocating.
  Checkpoint& c = f.checkpoint;
  const int n = c.cursor.grid;
  std::vector<std::pair<const char*, Field*>> expected = {{"phi", &c.result.phi}};
  if (c.stepper.nu_valid) expected.push_back({"nu", &c.stepper.nu});
  if (c.stepper.history_valid) {
    expected.push_back({"prev_phi", &c.stepper.prev_phi});
    expected.push_back({"prev_nu", &c.stepper.prev_nu});
  }
  if (fields.size() != expected.size())
    throw error(fmt::format("{} fields listed, {} expected", fields.size(), expected.size()));
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].first != expected[i].first || fields[i].second != n)
      throw error(fmt::format("field {} is '{}' on {}^3; expected '{}' on {}^3", i,
                              fields[i].first, fields[i].second, expected[i].first, n));
  const std::uint64_t cells = std::uint64_t(n) * n * n;
  const std::uint64_t data_bytes = cells * sizeof(double) * fields.size();
  const std::uint64_t want = kPreambleBytes + header_bytes + data_bytes + kTrailerBytes;
  if (size != want)
    throw error(fmt::format("{} bytes, but its header describes {} (truncated or padded)", size,
                            want));

  std::uint32_t crc = 0;
  std::vector<double> row(std::size_t(n), 0.0);
  for (auto& [field_name, field] : expected) {
    *field = Field(n, field_name == std::string("phi") ? 2 : 1);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j) {
        in.read(row.data(), row.size() * sizeof(double));
        crc = crc32_of(crc, row.data(), row.size() * sizeof(double));
        for (int i = 0; i < n; ++i) {
          if (!std::isfinite(row[std::size_t(i)]))
            throw error(fmt::format("field '{}' holds a non-finite value at cell ({}, {}, {})",
                                    field_name, i, j, k));
          (*field)(i, j, k) = row[std::size_t(i)];
        }
      }
    field->exchange_halo();
  }
  const auto data_crc = get<std::uint32_t>(in);
  std::array<char, 8> end{};
  in.read(end.data(), end.size());
  if (data_crc != crc || end != kEndMagic)
    throw error("the fields' checksum does not match (the file is corrupted)");
  return f;
}

}  // namespace

void write_checkpoint(const std::filesystem::path& path, const nlohmann::json& params,
                      const Checkpoint& c, const nlohmann::json& outputs) {
  const std::vector<NamedField> fields = fields_of(c);
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
  nlohmann::json list = nlohmann::json::array();
  for (const NamedField& f : fields) {
    if (!f.field->whole() || f.field->n() != c.cursor.grid)
      throw std::logic_error(fmt::format("write_checkpoint: field {} is not the whole {}^3 grid",
                                         f.name, c.cursor.grid));
    list.push_back({{"name", f.name}, {"n", f.field->n()}});
  }
  h["fields"] = list;
  const std::vector<std::uint8_t> header = nlohmann::json::to_cbor(h);

  AtomicWriter w(path);
  std::ostream& out = w.stream();
  out.write(kMagic.data(), kMagic.size());
  put(out, std::uint32_t(kCheckpointFormat));
  put(out, crc32_of(0, header.data(), header.size()));
  put(out, std::uint64_t(header.size()));
  out.write(reinterpret_cast<const char*>(header.data()), std::streamsize(header.size()));
  std::uint32_t crc = 0;
  for (const NamedField& f : fields) {
    const Field& x = *f.field;
    const std::streamsize row = std::streamsize(x.nx() * sizeof(double));
    for (int k = 0; k < x.nz(); ++k)
      for (int j = 0; j < x.ny(); ++j) {
        const double* p = &x(0, j, k);
        crc = crc32_of(crc, p, std::size_t(row));
        out.write(reinterpret_cast<const char*>(p), row);
      }
  }
  put(out, crc);
  out.write(kEndMagic.data(), kEndMagic.size());
  w.commit();
}

CheckpointFile read_checkpoint(const std::filesystem::path& path,
                               const CheckpointReadOptions& options) {
  std::unique_ptr<FileSource> in;
  try {
    in = std::make_unique<FileSource>(path);
    return parse(*in, options, path.string());
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
    return parse(in, options, name);
  } catch (const CheckpointError&) {
    throw;
  } catch (const std::exception& e) {
    throw CheckpointError(fmt::format("{}: {}", name, e.what()));
  }
}

}  // namespace cmcsurf
