#include "parallel/first_exception.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <new>
#include <stdexcept>
#include <vector>

namespace cmcsurf {
namespace {

TEST(FirstException, NothingThrownRethrowsNothing) {
  FirstException errors;
  int sum = 0;
#pragma omp parallel for num_threads(4) reduction(+ : sum)
  for (int k = 0; k < 100; ++k) errors.run([&] { sum += k; });
  EXPECT_FALSE(errors.failed());
  EXPECT_NO_THROW(errors.rethrow());
  EXPECT_EQ(sum, 4950);
}

// Every thread throws (a failed allocation on some, a runtime_error on others): the process
// lives, and exactly one of them reaches the caller after the region.
TEST(FirstException, OneOfTheThrownExceptionsReachesTheCaller) {
  FirstException errors;
#pragma omp parallel for num_threads(4) schedule(static, 1)
  for (int k = 0; k < 16; ++k)
    errors.run([&] {
      if (k % 2) throw std::bad_alloc();
      throw std::runtime_error("plane " + std::to_string(k));
    });
  EXPECT_TRUE(errors.failed());
  try {
    errors.rethrow();
    FAIL() << "rethrow() returned";
  } catch (const std::bad_alloc&) {
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("plane ", 0), 0u);
  }
}

// A real failed allocation inside a region (what a tight RLIMIT_AS causes): a bad_alloc after
// the region, no std::terminate.
TEST(FirstException, FailedAllocationInARegionIsABadAlloc) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer aborts on an impossible allocation instead of throwing";
#endif
  FirstException errors;
#pragma omp parallel num_threads(2)
  errors.run([] {
    volatile std::size_t bytes = std::size_t(1) << 62;  // more than any address space
    std::vector<char> huge(bytes);
    huge[0] = 1;
  });
  EXPECT_THROW(errors.rethrow(), std::bad_alloc);
}

}  // namespace
}  // namespace cmcsurf
