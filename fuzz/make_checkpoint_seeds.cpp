// Writes the valid seeds of fuzz/corpus/checkpoint/ with the real writer, and the broken ones
// as small edits of them or as hostile states written by it. Not part of any build; from the
// repository root, with a Release build in build-rel (its layers' libraries; no MPI):
//   g++ -std=c++20 -O1 -fopenmp -Isrc -DCMCSURF_VERSION='"0.1.0"' fuzz/make_checkpoint_seeds.cpp \
//       -Wl,--start-group build-rel/libcmcsurf_*.a -Wl,--end-group -lfmt -lz -lmuparser \
//       -o /tmp/make_checkpoint_seeds \
//     && /tmp/make_checkpoint_seeds
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <string>

#include <zlib.h>

#include "io/checkpoint.h"
#include "io/run_report.h"

namespace fs = std::filesystem;
using cmcsurf::Field;

namespace {

const fs::path kDir = "fuzz/corpus/checkpoint";

Field smooth(int n, int ghost, double shift) {
  Field f(n, ghost);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        f(i, j, k) = shift + 0.25 * std::sin(6.283185307179586 * (i + 2 * j + 3 * k) / n);
  f.exchange_halo();
  return f;
}

// A consistent state before step 3 of a 8^3 run: in the relaxation, or in the first mass
// correction's relaxation with all four stepper fields; or (coarse) before the second
// pre-relaxation step on the 8^3 level of a 16^3 run with one coarse level.
enum class Kind { kRelax, kVolume, kCoarsePrerelax };

cmcsurf::RunParams params_of(Kind kind) {
  cmcsurf::RunParams p;
  p.surface = "G";
  p.volume_fraction = 0.3;
  p.grid = kind == Kind::kCoarsePrerelax ? 16 : 8;
  p.epsilon = 0.1;
  p.coarse_levels = kind == Kind::kCoarsePrerelax ? 1 : 0;
  p.solver.extrapolate = kind == Kind::kVolume;
  return p;
}

cmcsurf::Checkpoint state(Kind kind) {
  const int n = 8;
  const int steps = kind == Kind::kCoarsePrerelax ? 1 : 2;
  cmcsurf::Checkpoint c;
  c.cursor.grid = n;
  c.cursor.stage = kind == Kind::kRelax    ? cmcsurf::RunStage::kRelax
                   : kind == Kind::kVolume ? cmcsurf::RunStage::kVolume
                                           : cmcsurf::RunStage::kPrerelax;
  c.cursor.stage_steps = steps;
  c.cursor.dt = 0.5 / n;
  c.cursor.area = 2.3;
  c.cursor.volume = 0.31;
  c.step = steps;
  c.time = steps * c.cursor.dt;
  c.elapsed = 0.25;
  c.result.phi = smooth(n, 2, 0.5);
  for (int s = 1; s <= steps; ++s) {
    cmcsurf::StepRecord r;
    r.step = s;
    r.stage = c.cursor.stage;
    r.time = s * c.cursor.dt;
    r.dt = c.cursor.dt;
    r.area = 2.3;
    r.vcycles = 3;
    c.result.history.push_back(r);
  }
  c.result.vcycles = 3 * steps;
  c.result.steps = kind == Kind::kCoarsePrerelax ? 0 : steps;
  if (kind == Kind::kVolume) {
    c.result.volume_constrained = true;
    c.result.volume_iterates.push_back({0.3, 0.29, 0, true});
    c.stepper.nu_valid = c.stepper.history_valid = true;
    c.stepper.prev_dt = c.cursor.dt;
    c.stepper.nu = smooth(n, 1, 0.0);
    c.stepper.prev_phi = smooth(n, 1, 0.49);
    c.stepper.prev_nu = smooth(n, 1, 0.01);
  }
  return c;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put(const std::string& name, const std::string& bytes) {
  std::ofstream(kDir / name, std::ios::binary) << bytes;
}

// Recomputes both CRC-32s, so that an edit reaches the checks behind them.
std::string with_checksums(std::string s) {
  std::uint64_t header = 0;
  std::memcpy(&header, s.data() + 16, 8);
  const auto* b = reinterpret_cast<const Bytef*>(s.data());
  const auto hcrc = std::uint32_t(crc32_z(0, b + 24, header));
  std::memcpy(s.data() + 12, &hcrc, 4);
  const std::size_t data = 24 + header;
  const auto dcrc = std::uint32_t(crc32_z(0, b + data, s.size() - 12 - data));
  std::memcpy(s.data() + s.size() - 12, &dcrc, 4);
  return s;
}

std::string edit(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  if (at == std::string::npos || from.size() != to.size())
    throw std::runtime_error("seed edit: no '" + from + "' or a length change");
  return s.replace(at, from.size(), to);
}

// A state written by the real writer after `edit`: valid checksums, hostile contents.
std::string written(Kind kind, const std::function<void(cmcsurf::Checkpoint&,
                                                        nlohmann::json&)>& edit) {
  cmcsurf::Checkpoint c = state(kind);
  nlohmann::json params = cmcsurf::params_json(params_of(kind));
  edit(c, params);
  const fs::path tmp = kDir / "tmp.bin";
  cmcsurf::write_checkpoint(tmp, params, c);
  std::string s = slurp(tmp);
  fs::remove(tmp);
  return s;
}

}  // namespace

int main() {
  fs::create_directories(kDir);
  for (const auto& e : fs::directory_iterator(kDir))
    if (e.path().filename().string().rfind("crash-", 0) != 0) fs::remove(e.path());
  auto same = [](cmcsurf::Checkpoint&, nlohmann::json&) {};
  const std::string a = written(Kind::kRelax, same);
  put("ok-relax-8.bin", a);
  put("ok-volume-8-stepper.bin", written(Kind::kVolume, same));
  put("ok-prerelax-coarse-level.bin", written(Kind::kCoarsePrerelax, same));
  std::uint64_t header = 0;
  std::memcpy(&header, a.data() + 16, 8);
  const std::size_t data = 24 + header;

  put("bad-empty.bin", "");
  put("bad-magic.bin", "CMCSCKPX" + a.substr(8));
  put("bad-truncated.bin", a.substr(0, a.size() - 100));
  put("bad-padded.bin", with_checksums(a + std::string(8, '\0')));
  {
    std::string s = a;
    s[data + 17] ^= 0x40;
    put("bad-field-checksum.bin", s);
    s = a;
    s[30] ^= 0x01;
    put("bad-header-checksum.bin", s);
  }
  {
    std::string s = a;
    const double q = std::nan("");
    std::memcpy(s.data() + data + 8 * 5, &q, 8);
    put("bad-nan.bin", with_checksums(s));
  }
  {
    std::string s = a;
    const std::uint64_t huge = std::uint64_t(1) << 62;
    std::memcpy(s.data() + 16, &huge, 8);
    put("bad-header-length.bin", s);
  }
  put("bad-stage.bin", with_checksums(edit(a, "relax", "relay")));
  // CBOR's text string of 5 bytes: the version, not the build identity that starts with it.
  put("bad-version.bin", with_checksums(edit(a, "\x65" "0.1.0", "\x65" "9.1.0")));
  // The zero-length header the first fuzzing run found (docs/reliability.md), in this format.
  {
    std::string s = "CMCSCKPT";
    const std::uint32_t format = cmcsurf::kCheckpointFormat, crc = 0;
    const std::uint64_t zero = 0;
    s.append(reinterpret_cast<const char*>(&format), 4);
    s.append(reinterpret_cast<const char*>(&crc), 4);
    s.append(reinterpret_cast<const char*>(&zero), 8);
    s.append(std::string(4, '\0') + "CKPTDONE");
    put("crash-empty-header.bin", s);
  }

  // Valid checksums, hostile contents (a crafted file must not reach the solver): parameters
  // out of range, a stage grid off the run's levels, seconds no clock holds (the reader
  // refuses these) ...
  put("bad-params-epsilon.bin", written(Kind::kRelax, [](auto&, auto& p) { p["epsilon"] = 2.0; }));
  put("bad-params-nan.bin",
      written(Kind::kRelax, [](auto&, auto& p) { p["tol"] = std::nan(""); }));
  put("bad-params-grid.bin", written(Kind::kRelax, [](auto&, auto& p) { p["grid"] = 50; }));
  put("bad-cursor-off-level.bin",
      written(Kind::kCoarsePrerelax, [](auto&, auto& p) { p["coarse_levels"] = 0; }));
  put("bad-elapsed.bin", written(Kind::kRelax, [](auto& c, auto&) { c.elapsed = 1e300; }));
  // ... and states no run of those parameters reaches (resume_problem refuses them; before,
  // they reached a back() on an empty vector, a CHECK or a signed overflow).
  put("bad-volume-no-iterates.bin", written(Kind::kVolume, [](auto& c, auto&) {
        c.result.volume_iterates.clear();
      }));
  put("bad-volume-correction.bin", written(Kind::kVolume, [](auto& c, auto& p) {
        c.cursor.correction = p["max_volume_corrections"].template get<int>();
      }));
  put("bad-coarse-level-of-sphere.bin", written(Kind::kCoarsePrerelax, [](auto&, auto& p) {
        p["surface"] = "sphere";
      }));
  put("bad-prerelax-on-finest.bin", written(Kind::kCoarsePrerelax, [](auto&, auto& p) {
        p["grid"] = 8;
        p["coarse_levels"] = 0;
        p["prerelax_steps"] = 1;  // the cursor is before pre-relaxation step 2 of 1
      }));
  put("bad-step-overflow.bin", written(Kind::kRelax, [](auto& c, auto&) {
        c.step = 2147483647;
        c.result.history.back().step = c.step;
      }));
  put("bad-vcycles-overflow.bin", written(Kind::kRelax, [](auto& c, auto&) {
        c.result.vcycles = 9223372036854775807L;
      }));
  return 0;
}
