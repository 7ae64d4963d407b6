// One fuzz target is one file fuzz/<name>_fuzz.cpp:
//
//   CMCSURF_FUZZ_TARGET(vti) {     // `input`: the bytes of one whole file
//     try { ...parse input... } catch (const std::runtime_error&) { return Outcome::refused; }
//     return Outcome::parsed;
//   }
//
// A target returns `parsed` or `refused` (the reader threw its documented error) and lets
// anything else escape: another exception, a failed require() or a sanitizer report is a
// finding. With -DCMCSURF_FUZZ=ON (clang) each file becomes a libFuzzer binary <name>_fuzz
// (fuzz/CMakeLists.txt); in the unit tests it is registered under its name, and
// fuzz/corpus_test.cpp runs every file of fuzz/corpus/<name>/ through it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace cmcsurf::fuzz {

using Input = std::span<const unsigned char>;
enum class Outcome { parsed, refused };
using TargetFn = Outcome (*)(Input);

// A property of a parsed result that the reader promises; a finding when it does not hold.
inline void require(bool cond, const std::string& what) {
  if (!cond) throw std::logic_error("fuzz target: " + what);
}

struct Target {
  const char* name;
  TargetFn run;
};

inline std::vector<Target>& targets() {
  static std::vector<Target> all;
  return all;
}

struct Registration {
  Registration(const char* name, TargetFn run) { targets().push_back({name, run}); }
};

}  // namespace cmcsurf::fuzz

#ifdef CMCSURF_LIBFUZZER
#define CMCSURF_FUZZ_TARGET(name)                                                   \
  static cmcsurf::fuzz::Outcome cmcsurf_fuzz_##name(cmcsurf::fuzz::Input input);    \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    cmcsurf_fuzz_##name(cmcsurf::fuzz::Input(data, size));                          \
    return 0;                                                                       \
  }                                                                                 \
  static cmcsurf::fuzz::Outcome cmcsurf_fuzz_##name(cmcsurf::fuzz::Input input)
#else
#define CMCSURF_FUZZ_TARGET(name)                                                       \
  static cmcsurf::fuzz::Outcome cmcsurf_fuzz_##name(cmcsurf::fuzz::Input input);        \
  static const cmcsurf::fuzz::Registration cmcsurf_fuzz_registration_##name(#name,      \
                                                                            cmcsurf_fuzz_##name); \
  static cmcsurf::fuzz::Outcome cmcsurf_fuzz_##name(cmcsurf::fuzz::Input input)
#endif
