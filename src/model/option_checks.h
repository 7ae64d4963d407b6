// The option checks that are not ranges of RunParams (those are finish_run_params's,
// model/run_options.h): --threads, which is no run parameter, and the sign of --seed, which
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
// The environment's OMP_NUM_THREADS (null: unset), which OpenMP obeys at the first parallel
// region, before any --threads applies: a count 1 <= T <= 4096 or a comma list of them (one
// per nesting level), spaces allowed around each. "" when accepted, else
// "got '100000'; accepted: ...". Anything else either starts that many threads (a crash at
// 100000) or is ignored by OpenMP with a warning.
std::string check_omp_num_threads(const char* value);

}  // namespace cmcsurf
