#include "model/option_checks.h"

#include <gtest/gtest.h>

namespace cmcsurf {
namespace {

TEST(OptionChecks, OmpNumThreadsAcceptsCountsAndNestingLists) {
  for (const char* ok : {static_cast<const char*>(nullptr), "1", "8", "4096", " 4 ", "4,2",
                         "8, 4 ,2"})
    EXPECT_EQ(check_omp_num_threads(ok), "") << (ok ? ok : "unset");
}

TEST(OptionChecks, OmpNumThreadsRefusesWhatOpenMpWouldMisread) {
  for (const char* bad : {"100000", "4097", "0", "", " ", "-1", "+4", "four", "4,", ",4",
                          "4,,2", "4;2", "2.5", "4,100000", "99999999999999999999"}) {
    const std::string why = check_omp_num_threads(bad);
    EXPECT_EQ(why.rfind(std::string("got '") + bad + "'; accepted: 1 <= T <= 4096", 0), 0u)
        << bad << ": " << why;
  }
}

}  // namespace
}  // namespace cmcsurf
