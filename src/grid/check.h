// Two tiers of programmer checks (docs/architecture.md): CMCSURF_CHECK is always on and
// aborts with the failed condition; CMCSURF_DCHECK is compiled only in checked builds
// (-DCMAKE_BUILD_TYPE=Checked defines CMCSURF_CHECKED) and its condition is not evaluated
// otherwise, so it may be expensive (a halo comparison, a scan of a field).
// User-facing errors are exceptions that name the bad input, not these.
#pragma once

namespace cmcsurf {

[[noreturn]] void check_failed(const char* condition, const char* file, int line);

}  // namespace cmcsurf

#define CMCSURF_CHECK(condition) \
  ((condition) ? (void)0 : ::cmcsurf::check_failed(#condition, __FILE__, __LINE__))

#ifdef CMCSURF_CHECKED
#define CMCSURF_DCHECK(condition) CMCSURF_CHECK(condition)
#else
#define CMCSURF_DCHECK(condition) ((void)sizeof(!(condition)))
#endif
