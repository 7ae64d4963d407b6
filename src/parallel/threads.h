// How many OpenMP threads each process of a run starts (docs/scaling.md, "Threads per rank").
// One process keeps OpenMP's own choice; under mpirun the processes of a node divide the CPUs
// they are bound to, so that P ranks never start P x cores spinning threads.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cmcsurf {

// A set of logical CPUs as sched_getaffinity reports them: bit c % 64 of word c / 64 is CPU c.
using CpuMask = std::vector<std::uint64_t>;
CpuMask cpu_mask(const std::vector<int>& cpus);
int cpu_count(const CpuMask& mask);
// The CPUs this process may run on (its binding), in CPU_SETSIZE / 64 words.
CpuMask affinity_cpus();

// The default thread count of process `self` among the processes of one node whose CPU sets
// are `node_masks`: its CPUs divided by the number of processes whose sets intersect its own
// (itself included), rounded down, at least 1. The processes holding a CPU all count each
// other, so the node's total never exceeds its CPUs unless it has more processes than CPUs.
int default_threads(const std::vector<CpuMask>& node_masks, int self);

struct ThreadChoice {
  int threads = 1;            // this process's OpenMP threads
  std::string source;         // "--threads", "OMP_NUM_THREADS" or "cores"
  std::vector<int> per_rank;  // every process's threads in MPI_COMM_WORLD rank order
  // "" unless an explicit count (--threads, OMP_NUM_THREADS) puts more threads on a node than
  // it has CPUs and than it has processes; the same text on every process.
  std::string warning;
};

// Sets this process's OpenMP thread count: `requested` when > 0, else OMP_NUM_THREADS when it
// holds a positive count, else OpenMP's default for one process (every CPU of its affinity
// mask) and default_threads over the processes of its node under mpirun. Collective when the
// run has several processes: every one calls it at the same point.
ThreadChoice choose_threads(int requested);
// per_rank of this process's last choose_threads (empty before the first).
const std::vector<int>& threads_per_rank();

}  // namespace cmcsurf
