// Wall-clock time of a stage, as report.json's *_seconds keys give it.
#pragma once

#include <chrono>

namespace cmcsurf {

using WallClock = std::chrono::steady_clock;

// Seconds from t0 (WallClock::now() taken at the start of the stage) to now.
inline double seconds_since(WallClock::time_point t0) {
  return std::chrono::duration<double>(WallClock::now() - t0).count();
}

}  // namespace cmcsurf
