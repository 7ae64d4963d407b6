#include "parallel/threads.h"

#include <gtest/gtest.h>
#include <omp.h>

namespace cmcsurf {
namespace {

// Every process's default on one node.
std::vector<int> defaults(const std::vector<CpuMask>& masks) {
  std::vector<int> t;
  for (int i = 0; i < int(masks.size()); ++i) t.push_back(default_threads(masks, i));
  return t;
}

TEST(Threads, MasksCountTheirCpus) {
  EXPECT_EQ(cpu_count(cpu_mask({})), 0);
  EXPECT_EQ(cpu_count(cpu_mask({0, 1, 63, 64, 1023})), 5);
  EXPECT_EQ(cpu_mask({64}), (CpuMask{0, 1}));
  EXPECT_GE(cpu_count(affinity_cpus()), 1);
}

TEST(Threads, RanksDivideTheCpusTheyShare) {
  // One process bound to 8 CPUs takes them all.
  EXPECT_EQ(defaults({cpu_mask({0, 1, 2, 3, 4, 5, 6, 7})}), (std::vector<int>{8}));
  // 4 unbound (oversubscribed) ranks on 2 CPUs: 1 each, not 2.
  const CpuMask two = cpu_mask({0, 1});
  EXPECT_EQ(defaults({two, two, two, two}), (std::vector<int>{1, 1, 1, 1}));
  // 2 ranks sharing 8 CPUs: 4 each.
  const CpuMask eight = cpu_mask({0, 1, 2, 3, 4, 5, 6, 7});
  EXPECT_EQ(defaults({eight, eight}), (std::vector<int>{4, 4}));
  // Bound to one core each (mpirun -np 2 --bind-to core): 1 each.
  EXPECT_EQ(defaults({cpu_mask({0}), cpu_mask({1})}), (std::vector<int>{1, 1}));
  // Bound to disjoint sockets of 4 (--bind-to socket, one rank per socket): 4 each.
  EXPECT_EQ(defaults({cpu_mask({0, 1, 2, 3}), cpu_mask({4, 5, 6, 7}), cpu_mask({64, 65, 66, 67})}),
            (std::vector<int>{4, 4, 4}));
  // Two ranks per socket of 4 on two sockets: 2 each, 8 threads on 8 CPUs.
  const CpuMask s0 = cpu_mask({0, 1, 2, 3}), s1 = cpu_mask({4, 5, 6, 7});
  EXPECT_EQ(defaults({s0, s0, s1, s1}), (std::vector<int>{2, 2, 2, 2}));
  // Partial overlap: a rank on all 8 CPUs and one on 4 of them count each other (6 <= 8).
  EXPECT_EQ(defaults({eight, s0}), (std::vector<int>{4, 2}));
  // An empty mask (no information) still runs.
  EXPECT_EQ(defaults({cpu_mask({})}), (std::vector<int>{1}));
}

// Never more threads on a node than CPUs, except one thread for each rank with fewer CPUs
// than ranks sharing them: random bindings of up to 12 ranks on 8 CPUs.
TEST(Threads, NodeTotalNeverExceedsItsCpus) {
  unsigned seed = 12345;
  auto next = [&] { return seed = seed * 1103515245u + 12345u, (seed >> 16) & 0x7fff; };
  for (int trial = 0; trial < 5000; ++trial) {
    const int ranks = 1 + int(next() % 12);
    std::vector<CpuMask> masks;
    for (int r = 0; r < ranks; ++r) {
      std::vector<int> cpus;
      for (int c = 0; c < 8; ++c)
        if (next() % 2) cpus.push_back(c);
      if (cpus.empty() || next() % 2 == 0) cpus = {int(next() % 8)};
      masks.push_back(cpu_mask(cpus));
    }
    int union_cpus = 0;
    for (int c = 0; c < 8; ++c)
      for (const CpuMask& m : masks)
        if (m[0] >> c & 1) {
          ++union_cpus;
          break;
        }
    int total = 0, starved = 0;
    for (int r = 0; r < ranks; ++r) {
      total += default_threads(masks, r);
      int sharers = 0;
      for (const CpuMask& m : masks) sharers += (m[0] & masks[r][0]) ? 1 : 0;
      starved += cpu_count(masks[r]) < sharers ? 1 : 0;
    }
    ASSERT_LE(total, union_cpus + starved) << "trial " << trial;
    if (starved == 0) {
      ASSERT_LE(total, union_cpus) << "trial " << trial;
    }
  }
}

// One process: --threads T as given, 0 keeps OpenMP's own count.
TEST(Threads, OneProcessKeepsOpenMpsChoice) {
  const int before = omp_get_max_threads();
  ThreadChoice c = choose_threads(3);
  EXPECT_EQ(c.threads, 3);
  EXPECT_EQ(omp_get_max_threads(), 3);
  EXPECT_EQ(c.source, "--threads");
  EXPECT_EQ(c.per_rank, (std::vector<int>{3}));
  EXPECT_EQ(threads_per_rank(), (std::vector<int>{3}));
  EXPECT_TRUE(c.warning.empty());
  omp_set_num_threads(before);
  c = choose_threads(0);
  EXPECT_EQ(c.threads, before);
  EXPECT_NE(c.source, "--threads");
}

}  // namespace
}  // namespace cmcsurf
