// The identity of this build: what a checkpoint must share with the program that resumes it,
// since another compiler, flag or commit may take other V-cycles (docs/reliability.md).
// Generated at configure time into one source file (src/io/build_info.cpp.in), so that a new
// commit recompiles that file alone.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace cmcsurf {

struct BuildInfo {
  std::string version;     // the project's (CMCSURF_VERSION)
  std::string commit;      // git commit when CMake configured the build; "unknown" without git
  std::string compiler;    // id and version, e.g. "GNU 12.2.0"
  std::string build_type;  // CMAKE_BUILD_TYPE
  std::string flags;       // the flags that change arithmetic: optimisation, -march, sanitizers
  std::string target;      // the instruction set the compiler targeted (its predefined macros)
};

const BuildInfo& build_info();
// {version, commit, compiler, build_type, flags, target}: report.json's "build".
nlohmann::json build_info_json();
// One line naming all of it; two builds that may compute different bits differ in it.
std::string build_identity();

}  // namespace cmcsurf
