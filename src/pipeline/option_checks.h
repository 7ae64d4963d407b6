// The option checks that are not ranges of RunParams (those are finish_run_params's,
// pipeline/run_options.h): --threads, which is no run parameter, and the sign of --seed, which
// an unsigned RunParams::seed cannot hold. The command line (CLI11 checks, apps/cli_common.cpp)
// and the Python module call these, so both say the same. Each returns "" when the value is
// accepted, else what follows "--option: " in the message.
#pragma once

#include <string>

namespace cmcsurf {

constexpr int kMaxThreads = 4096;

// "got -1; accepted: 0 <= T <= 4096 (0: OMP_NUM_THREADS or all cores)"
std::string check_threads(long long threads);
// "got -1; accepted: 0 <= S < 2^64"
std::string check_seed(long long seed);

}  // namespace cmcsurf
