// How much memory this process may still take: the smallest of the address-space limit
// (RLIMIT_AS, less what is mapped now), the cgroup's limit (less what the cgroup uses) and the
// system's MemAvailable. A run checks its estimate against it before the solve, so that a grid
// too large is refused with the figures instead of failing after minutes of work.
#pragma once

#include <cstdint>
#include <string>

namespace cmcsurf {

struct MemoryHeadroom {
  std::uint64_t bytes = UINT64_MAX;  // UINT64_MAX: nothing limits it that we could read
  std::string source;                // "RLIMIT_AS", "cgroup memory.max", "MemAvailable"
};
MemoryHeadroom memory_headroom();

// "1.5 GB", "870 MB": for messages.
std::string format_bytes(std::uint64_t bytes);

}  // namespace cmcsurf
