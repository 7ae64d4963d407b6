// The processes of a run and how the periodic N^3 grid is split among them: a 3D Cartesian
// block decomposition (MPI_Cart_create, periodic in x, y and z) with equal blocks, or one
// process owning everything. MPI appears only in decomposition.cpp; without CMCSURF_HAVE_MPI
// every process is alone and the collectives are identities.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace cmcsurf {

// A process's part of an N^3 grid: cells ox..ox+nx-1 along x (and so on), h = 1/n.
struct Block {
  int n = 0;
  std::array<int, 3> size{};    // nx, ny, nz
  std::array<int, 3> offset{};  // global index of the block's first cell per axis
};

// Blocks of a distributed multigrid level are at least this many cells per axis; coarser
// levels are gathered onto every process (docs/scaling.md).
constexpr int kMinBlockCells = 4;

// What this process has sent, and the time it spent in communication calls (wall clock,
// waiting for neighbours included).
struct CommStats {
  double halo_bytes = 0.0;  // face exchanges (sent)
  long halo_messages = 0;
  double gather_bytes = 0.0;  // allgathers, gathers and reductions (sent)
  long collectives = 0;
  double seconds = 0.0;
};

struct ProcessGroup;  // below: a group of the world's processes (Decomposition::split)

class Decomposition {
 public:
  // Every process of the run (MPI_COMM_WORLD) on a periodic process grid from MPI_Dims_create;
  // z is split first (the largest factor), then y, then x. One process without MPI. The first
  // call after MPI_Init is collective; later calls return the same object.
  static std::shared_ptr<const Decomposition> world();
  // A single process owning the whole grid (for serial fields and tests).
  static std::shared_ptr<const Decomposition> self();

  int ranks() const { return ranks_; }
  int rank() const { return rank_; }
  bool distributed() const { return ranks_ > 1; }
  const std::array<int, 3>& dims() const { return dims_; }  // processes along x, y, z
  const std::array<int, 3>& coords() const { return coords_; }
  std::array<int, 3> coords_of(int rank) const;
  // Rank of the neighbour along axis in direction dir (-1 or +1), periodic.
  int neighbour(int axis, int dir) const { return neighbours_[axis][dir > 0]; }

  // "" when every process gets an equal block of at least kMinBlockCells per axis; otherwise a
  // message naming N, the process grid and the sizes that would work.
  std::string check_grid(int n) const;
  bool splits(int n) const { return check_grid(n).empty(); }
  Block block(int n) const { return block_of(rank_, n); }
  Block block_of(int rank, int n) const;

  // Sums over all processes, added in rank order so every process gets the same bits.
  double sum(double local) const;
  void sum(double* values, int count) const;
  double max(double local) const;
  // The largest exit code over the processes. Waits by polling with short sleeps, so that
  // processes done early do not spin while rank 0 writes the output.
  int max_exit_code(int code) const;
  // Sends send_lo to the low neighbour along axis and send_hi to the high one, and receives
  // recv_lo from the low and recv_hi from the high neighbour (count doubles each; non-blocking
  // sends and receives, then a wait).
  void exchange(int axis, const double* send_lo, const double* send_hi, double* recv_lo,
                double* recv_hi, std::size_t count) const;
  // Concatenates every process's `count` values in rank order, on every process (all) or on
  // rank 0 only (recv may be null elsewhere).
  void allgather(const double* send, std::size_t count, double* recv) const;
  void gather(const double* send, std::size_t count, double* recv) const;
  void broadcast(double* values, int count) const;  // from rank 0
  // Block-wise outputs after a run (render/draw_surface.cpp, pipeline/distributed_mesh.cpp):
  // Element-wise sums onto rank 0 (values is left undefined elsewhere). Exact where at most
  // one process contributes a non-zero to each element, whatever order MPI adds in.
  void sum_to_root(double* values, std::size_t count) const;
  // Every process's vector, concatenated in rank order on rank 0 (empty elsewhere); counts,
  // if given, gets each process's size on rank 0.
  std::vector<double> gather_varying(const std::vector<double>& send,
                                     std::vector<int>* counts = nullptr) const;
  // Rank 0's vector (its size included) on every process.
  void broadcast_vector(std::vector<double>& values) const;
  const CommStats& stats() const { return stats_; }

  // Ends every process of the run (for an error that only some processes saw).
  [[noreturn]] void abort_all(int code) const;

  // --- Agreement after per-process file I/O (io/pvti.*, io/checkpoint.*: each process writes
  // or reads its own piece, and all must then succeed or fail together) ---
  // Every process passes its error message ("" for none) and gets the message of the lowest
  // rank that failed ("" if none did), the same on every process; `rank`, if given, gets
  // that rank (-1 for none).
  std::string first_error(const std::string& mine, int* rank = nullptr) const;

  // --- Process groups: a sweep's members side by side (docs/scaling.md) ---
  // Splits the world's processes into `groups` groups of ranks() / groups consecutive world
  // ranks, each on its own periodic process grid built as world()'s (a group of one process is
  // self()). Collective over the world; `groups` must divide the world's rank count.
  static ProcessGroup split(int groups);
  // check_grid(n) on the process grid `ranks` processes get (MPI_Dims_create, as in world() and
  // split()), without building it. ranks > 1 needs MPI.
  static std::string check_grid_for(int ranks, int n);

 private:
  struct Comm;
  std::shared_ptr<Comm> comm_;  // null: a single process
  // Lays this object's process grid over the processes of `processes` (collective over them).
  void arrange(const Comm& processes);
  int ranks_ = 1;
  int rank_ = 0;
  std::array<int, 3> dims_{1, 1, 1};
  std::array<int, 3> coords_{0, 0, 0};
  std::array<std::array<int, 2>, 3> neighbours_{};
  mutable CommStats stats_;
};

// Start-up collectives over every process of the run (MPI_COMM_WORLD), kept out of any
// Decomposition's CommStats; every process passes the same number of values. Without MPI, before
// MPI_Init or on one process they return `mine` alone.
struct NodeGather {
  int node_rank = 0;                  // this process among those on its node
  int node_ranks = 1;                 // processes on its node (MPI_COMM_TYPE_SHARED)
  std::vector<std::uint64_t> values;  // node_ranks x mine.size(), in node rank order
};
NodeGather allgather_on_node(const std::vector<std::uint64_t>& mine);
// ranks x mine.size(), in MPI_COMM_WORLD rank order (= Decomposition::world()'s rank).
std::vector<std::uint64_t> allgather_world(const std::vector<std::uint64_t>& mine);

// --- Process groups: a sweep's members side by side (docs/scaling.md) ---
struct ProcessGroup {
  int groups = 1;  // the world's processes form this many groups of equal size
  int index = 0;   // this process's group: world ranks index * size .. (index + 1) * size - 1
  std::shared_ptr<const Decomposition> decomposition;  // the group's processes
};
// Every process's bytes, in MPI_COMM_WORLD rank order, on world rank 0 (empty elsewhere), kept
// out of any CommStats; rank 0 waits with short sleeps, so a process done early does not spin
// while the others compute. Collective over the world; {mine} on one process.
std::vector<std::string> gather_world_bytes(const std::string& mine);

// MPI_Init / MPI_Finalize around main (nothing without MPI).
class ParallelSession {
 public:
  ParallelSession(int* argc, char*** argv);
  ~ParallelSession();
  ParallelSession(const ParallelSession&) = delete;
  ParallelSession& operator=(const ParallelSession&) = delete;
};

}  // namespace cmcsurf
