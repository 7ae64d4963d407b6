// Threads per rank under mpirun -np 2 and -np 4 on one machine (CTest label mpi): the start-up
// collectives and choose_threads (docs/scaling.md, "Threads per rank"). Every collective runs
// before the assertions, so a failure on one rank cannot leave another waiting.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdlib>
#include <string>
#include <thread>

#include "parallel/decomposition.h"
#include "parallel/threads.h"

namespace cmcsurf {
namespace {

TEST(Threads, StartUpGathersSeeEveryRankInOrder) {
  const auto world = Decomposition::world();
  const std::uint64_t r = std::uint64_t(world->rank());
  const NodeGather node = allgather_on_node({r, 7});
  const std::vector<std::uint64_t> all = allgather_world({3 * r});
  // One machine: its node holds every rank, in world order (MPI_Comm_split_type's key 0).
  EXPECT_EQ(node.node_ranks, world->ranks());
  EXPECT_EQ(node.node_rank, world->rank());
  ASSERT_EQ(node.values.size(), 2 * std::size_t(world->ranks()));
  ASSERT_EQ(all.size(), std::size_t(world->ranks()));
  for (int i = 0; i < world->ranks(); ++i) {
    EXPECT_EQ(node.values[2 * i], std::uint64_t(i));
    EXPECT_EQ(node.values[2 * i + 1], 7u);
    EXPECT_EQ(all[i], 3u * i);
  }
}

// OMP_NUM_THREADS unset (CTest sets it to 1 for the mpi tests) for one scope.
class WithoutOmpNumThreads {
 public:
  WithoutOmpNumThreads() : before_(omp_get_max_threads()) {
    if (const char* v = std::getenv("OMP_NUM_THREADS")) saved_ = v, had_ = true;
    unsetenv("OMP_NUM_THREADS");
  }
  ~WithoutOmpNumThreads() {
    if (had_) setenv("OMP_NUM_THREADS", saved_.c_str(), 1);
    omp_set_num_threads(before_);
  }

 private:
  int before_;
  std::string saved_;
  bool had_ = false;
};

TEST(Threads, DefaultSharesTheCpusOfTheMachine) {
  const WithoutOmpNumThreads scope;
  const auto world = Decomposition::world();
  const ThreadChoice c = choose_threads(0);
  const int in_use = omp_get_max_threads();
  CpuMask mine = affinity_cpus();
  const NodeGather node = allgather_on_node(mine);
  std::vector<CpuMask> masks;
  CpuMask machine(mine.size(), 0);
  for (int i = 0; i < node.node_ranks; ++i) {
    masks.emplace_back(node.values.begin() + std::ptrdiff_t(i * mine.size()),
                       node.values.begin() + std::ptrdiff_t((i + 1) * mine.size()));
    for (std::size_t w = 0; w < mine.size(); ++w) machine[w] |= masks.back()[w];
  }
  EXPECT_EQ(c.source, "cores");
  EXPECT_EQ(in_use, c.threads);
  EXPECT_EQ(c.threads, default_threads(masks, node.node_rank));
  EXPECT_TRUE(c.warning.empty()) << c.warning;
  ASSERT_EQ(c.per_rank.size(), std::size_t(world->ranks()));
  EXPECT_EQ(c.per_rank[world->rank()], c.threads);
  EXPECT_EQ(threads_per_rank(), c.per_rank);
  int total = 0;
  for (int t : c.per_rank) {
    EXPECT_GE(t, 1);
    total += t;
  }
  // ranks x threads on this machine: at most its CPUs (one thread each when fewer CPUs).
  EXPECT_LE(total, std::max(cpu_count(machine), world->ranks()));
}

TEST(Threads, ExplicitCountsAreKeptAndOversubscriptionWarned) {
  const WithoutOmpNumThreads scope;
  const auto world = Decomposition::world();
  const int cpus = int(std::thread::hardware_concurrency());  // the machine's, on every rank
  const ThreadChoice option = choose_threads(1);
  setenv("OMP_NUM_THREADS", std::to_string(cpus + 1).c_str(), 1);
  const ThreadChoice env = choose_threads(0);
  EXPECT_EQ(option.source, "--threads");
  EXPECT_EQ(option.per_rank, std::vector<int>(world->ranks(), 1));
  EXPECT_TRUE(option.warning.empty()) << option.warning;  // 1 per rank never warns
  EXPECT_EQ(env.source, "OMP_NUM_THREADS");
  EXPECT_EQ(env.per_rank, std::vector<int>(world->ranks(), cpus + 1));
  EXPECT_NE(env.warning.find("OpenMP threads"), std::string::npos);  // P (cpus + 1) > cpus and P
}

}  // namespace
}  // namespace cmcsurf
