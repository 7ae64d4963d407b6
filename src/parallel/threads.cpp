#include "parallel/threads.h"

#include <fmt/format.h>
#include <omp.h>
#include <sched.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdlib>
#include <thread>

#include "parallel/decomposition.h"

namespace cmcsurf {

namespace {

constexpr std::size_t kCpuMaskWords = CPU_SETSIZE / 64;

bool intersect(const CpuMask& a, const CpuMask& b) {
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t w = 0; w < n; ++w)
    if (a[w] & b[w]) return true;
  return false;
}

// The first count of OMP_NUM_THREADS ("8" or "8,4"), 0 when unset or not a positive count
// (OpenMP then ignores it too).
int omp_num_threads_env() {
  const char* text = std::getenv("OMP_NUM_THREADS");
  if (text == nullptr) return 0;
  char* end = nullptr;
  const long n = std::strtol(text, &end, 10);
  if (end == text || n <= 0 || n > (1L << 20)) return 0;
  while (std::isspace(static_cast<unsigned char>(*end))) ++end;
  return (*end == '\0' || *end == ',') ? int(n) : 0;
}

std::vector<int> last_per_rank;

}  // namespace

CpuMask cpu_mask(const std::vector<int>& cpus) {
  CpuMask mask;
  for (int c : cpus) {
    if (std::size_t(c) / 64 >= mask.size()) mask.resize(std::size_t(c) / 64 + 1, 0);
    mask[std::size_t(c) / 64] |= std::uint64_t(1) << (c % 64);
  }
  return mask;
}

int cpu_count(const CpuMask& mask) {
  int n = 0;
  for (std::uint64_t w : mask) n += std::popcount(w);
  return n;
}

CpuMask affinity_cpus() {
  CpuMask mask(kCpuMaskWords, 0);
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) {
    for (int c = 0; c < CPU_SETSIZE; ++c)
      if (CPU_ISSET(c, &set)) mask[c / 64] |= std::uint64_t(1) << (c % 64);
  } else {  // no mask: every CPU the system reports
    const int n = std::clamp(int(std::thread::hardware_concurrency()), 1, CPU_SETSIZE);
    for (int c = 0; c < n; ++c) mask[c / 64] |= std::uint64_t(1) << (c % 64);
  }
  return mask;
}

int default_threads(const std::vector<CpuMask>& node_masks, int self) {
  const CpuMask& mine = node_masks.at(std::size_t(self));
  const int cpus = cpu_count(mine);
  if (cpus == 0) return 1;
  int sharers = 0;  // itself included
  for (const CpuMask& other : node_masks) sharers += intersect(mine, other) ? 1 : 0;
  return std::max(1, cpus / sharers);
}

ThreadChoice choose_threads(int requested) {
  ThreadChoice c;
  const int env = omp_num_threads_env();
  const int explicit_count = requested > 0 ? requested : env;
  c.source = requested > 0 ? "--threads" : env > 0 ? "OMP_NUM_THREADS" : "cores";

  if (Decomposition::world()->ranks() == 1) {
    // Alone: OpenMP's own default (OMP_NUM_THREADS or every CPU of the affinity mask).
    if (requested > 0) omp_set_num_threads(requested);
    c.threads = omp_get_max_threads();
    c.per_rank = last_per_rank = {c.threads};
    return c;
  }
  // Every process's CPUs and explicit count (0: none) on this node.
  CpuMask mine = affinity_cpus();
  mine.push_back(std::uint64_t(explicit_count));
  const NodeGather node = allgather_on_node(mine);
  const std::size_t words = mine.size();
  std::vector<CpuMask> masks(node.node_ranks);
  std::vector<int> given(node.node_ranks);
  CpuMask node_cpus(words - 1, 0);
  for (int i = 0; i < node.node_ranks; ++i) {
    const auto first = node.values.begin() + std::ptrdiff_t(i * words);
    masks[i].assign(first, first + std::ptrdiff_t(words - 1));
    given[i] = int(node.values[i * words + words - 1]);
    for (std::size_t w = 0; w + 1 < words; ++w) node_cpus[w] |= masks[i][w];
  }
  long node_threads = 0;
  bool node_given = false;  // some process here chose its count
  for (int i = 0; i < node.node_ranks; ++i) {
    node_threads += given[i] > 0 ? given[i] : default_threads(masks, i);
    node_given = node_given || given[i] > 0;
  }
  c.threads = explicit_count > 0 ? explicit_count : default_threads(masks, node.node_rank);
  omp_set_num_threads(c.threads);

  constexpr std::size_t kValues = 5;
  const std::vector<std::uint64_t> all = allgather_world(
      {std::uint64_t(c.threads), std::uint64_t(node_threads), std::uint64_t(cpu_count(node_cpus)),
       std::uint64_t(node.node_ranks), std::uint64_t(node_given)});
  const std::size_t ranks = all.size() / kValues;
  c.per_rank.resize(ranks);
  for (std::size_t r = 0; r < ranks; ++r) {
    const std::uint64_t* v = &all[kValues * r];
    c.per_rank[r] = int(v[0]);
    const std::uint64_t threads = v[1], cpus = v[2], procs = v[3];
    if (c.warning.empty() && v[4] != 0 && threads > std::max(cpus, procs))
      c.warning = fmt::format(
          "{} OpenMP threads on the {} CPUs of rank {}'s node ({} ranks there, counts from "
          "--threads or OMP_NUM_THREADS): threads waiting for shared cores slow a run down by "
          "orders of magnitude; with --threads 0 and OMP_NUM_THREADS unset, each rank takes its "
          "share of the CPUs it is bound to",
          threads, cpus, r, procs);
  }
  last_per_rank = c.per_rank;
  return c;
}

const std::vector<int>& threads_per_rank() { return last_per_rank; }

}  // namespace cmcsurf
