#include "parallel/decomposition.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <thread>
#include <vector>

#include "common/wall_clock.h"

#ifdef CMCSURF_HAVE_MPI
#include <mpi.h>
#endif

namespace cmcsurf {

namespace {

// Adds the wall time of its scope to `seconds`.
class CommTimer {
 public:
  explicit CommTimer(double& seconds) : seconds_(seconds) {}
  ~CommTimer() {
    seconds_ += seconds_since(t0_);
  }

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

}  // namespace

#ifdef CMCSURF_HAVE_MPI
struct Decomposition::Comm {
  MPI_Comm cart = MPI_COMM_NULL;
  ~Comm() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized && cart != MPI_COMM_NULL) MPI_Comm_free(&cart);
  }
};
#else
struct Decomposition::Comm {};
#endif

std::shared_ptr<const Decomposition> Decomposition::self() {
  static const auto single = std::make_shared<const Decomposition>();
  return single;
}

std::shared_ptr<const Decomposition> Decomposition::world() {
#ifdef CMCSURF_HAVE_MPI
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) return self();
  // Built once (MPI_Cart_create is collective): every later call returns the same object.
  static std::shared_ptr<const Decomposition> cached;
  if (cached) return cached;
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (ranks == 1) return cached = self();
  auto d = std::make_shared<Decomposition>();
  Comm all;  // a duplicate of MPI_COMM_WORLD, freed once the process grid is laid over it
  MPI_Comm_dup(MPI_COMM_WORLD, &all.cart);
  d->arrange(all);
  return cached = d;
#else
  return self();
#endif
}

std::array<int, 3> Decomposition::coords_of(int rank) const {
  std::array<int, 3> c{0, 0, 0};
#ifdef CMCSURF_HAVE_MPI
  if (comm_) {
    int cart[3];
    MPI_Cart_coords(comm_->cart, rank, 3, cart);
    for (int a = 0; a < 3; ++a) c[a] = cart[2 - a];
  }
#else
  (void)rank;
#endif
  return c;
}

namespace {
// Decomposition::check_grid on a process grid of `ranks` processes, `dims` along x, y, z.
std::string grid_problem(const std::array<int, 3>& dims, int ranks, int n) {
  for (int a = 0; a < 3; ++a) {
    const int p = dims[a];
    if (n % (2 * p) != 0 || n / p < kMinBlockCells)
      return fmt::format(
          "N = {} does not split into equal blocks of an even number (>= {}) of cells on the "
          "{} x {} x {} process grid of {} ranks: N must be a multiple of 2 x {} with N / {} >= "
          "{} along every axis; choose another N or another number of ranks",
          n, kMinBlockCells, dims[0], dims[1], dims[2], ranks, p, p, kMinBlockCells);
  }
  return "";
}
}  // namespace

std::string Decomposition::check_grid(int n) const { return grid_problem(dims_, ranks_, n); }

Block Decomposition::block_of(int rank, int n) const {
  const std::array<int, 3> c = coords_of(rank);
  Block b;
  b.n = n;
  for (int a = 0; a < 3; ++a) {
    b.size[a] = n / dims_[a];
    b.offset[a] = c[a] * b.size[a];
  }
  return b;
}

double Decomposition::sum(double local) const {
  sum(&local, 1);
  return local;
}

void Decomposition::sum(double* values, int count) const {
  if (!comm_) return;
  std::vector<double> all(std::size_t(count) * ranks_);
  allgather(values, std::size_t(count), all.data());
  for (int c = 0; c < count; ++c) {
    double s = 0.0;
    for (int r = 0; r < ranks_; ++r) s += all[std::size_t(r) * count + c];
    values[c] = s;
  }
}

double Decomposition::max(double local) const {
  if (!comm_) return local;
  std::vector<double> all(ranks_);
  allgather(&local, 1, all.data());
  return *std::max_element(all.begin(), all.end());
}

int Decomposition::max_exit_code(int code) const {
#ifdef CMCSURF_HAVE_MPI
  if (comm_) {
    int worst = code;
    MPI_Request request;
    MPI_Iallreduce(&code, &worst, 1, MPI_INT, MPI_MAX, comm_->cart, &request);
    for (int done = 0;;) {
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
      if (done) return worst;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
#endif
  return code;
}

void Decomposition::exchange(int axis, const double* send_lo, const double* send_hi,
                             double* recv_lo, double* recv_hi, std::size_t count) const {
#ifdef CMCSURF_HAVE_MPI
  if (comm_) {
    const CommTimer timer(stats_.seconds);
    stats_.halo_bytes += 2.0 * sizeof(double) * count;
    stats_.halo_messages += 2;
    const int lo = neighbours_[axis][0], hi = neighbours_[axis][1];
    const int c = int(count);
    MPI_Request req[4];
    // Tag 0 travels up (a high face into the neighbour's low ghosts), tag 1 travels down.
    MPI_Irecv(recv_lo, c, MPI_DOUBLE, lo, 0, comm_->cart, &req[0]);
    MPI_Irecv(recv_hi, c, MPI_DOUBLE, hi, 1, comm_->cart, &req[1]);
    MPI_Isend(send_hi, c, MPI_DOUBLE, hi, 0, comm_->cart, &req[2]);
    MPI_Isend(send_lo, c, MPI_DOUBLE, lo, 1, comm_->cart, &req[3]);
    MPI_Waitall(4, req, MPI_STATUSES_IGNORE);
    return;
  }
#else
  (void)axis;
#endif
  // One process: both neighbours are this process.
  std::memcpy(recv_lo, send_hi, sizeof(double) * count);
  std::memcpy(recv_hi, send_lo, sizeof(double) * count);
}

void Decomposition::allgather(const double* send, std::size_t count, double* recv) const {
#ifdef CMCSURF_HAVE_MPI
  if (comm_) {
    const CommTimer timer(stats_.seconds);
    stats_.gather_bytes += sizeof(double) * count;
    ++stats_.collectives;
    MPI_Allgather(send, int(count), MPI_DOUBLE, recv, int(count), MPI_DOUBLE, comm_->cart);
    return;
  }
#endif
  std::memcpy(recv, send, sizeof(double) * count);
}

void Decomposition::gather(const double* send, std::size_t count, double* recv) const {
#ifdef CMCSURF_HAVE_MPI
  if (comm_) {
    const CommTimer timer(stats_.seconds);
    stats_.gather_bytes += sizeof(double) * count;
    ++stats_.collectives;
    MPI_Gather(send, int(count), MPI_DOUBLE, recv, int(count), MPI_DOUBLE, 0, comm_->cart);
    return;
  }
#endif
  std::memcpy(recv, send, sizeof(double) * count);
}

void Decomposition::broadcast(double* values, int count) const {
#ifdef CMCSURF_HAVE_MPI
  if (comm_) MPI_Bcast(values, count, MPI_DOUBLE, 0, comm_->cart);
#else
  (void)values;
  (void)count;
#endif
}

// --- Collectives of the block-wise outputs (measures, pictures, meshes after a run) ---

void Decomposition::sum_to_root(double* values, std::size_t count) const {
#ifdef CMCSURF_HAVE_MPI
  if (comm_) {
    const CommTimer timer(stats_.seconds);
    stats_.gather_bytes += sizeof(double) * count;
    ++stats_.collectives;
    if (rank_ == 0)
      MPI_Reduce(MPI_IN_PLACE, values, int(count), MPI_DOUBLE, MPI_SUM, 0, comm_->cart);
    else
      MPI_Reduce(values, nullptr, int(count), MPI_DOUBLE, MPI_SUM, 0, comm_->cart);
    return;
  }
#endif
  (void)values;
  (void)count;
}

std::vector<double> Decomposition::gather_varying(const std::vector<double>& send,
                                                  std::vector<int>* counts) const {
#ifdef CMCSURF_HAVE_MPI
  if (comm_) {
    const CommTimer timer(stats_.seconds);
    stats_.gather_bytes += sizeof(double) * send.size();
    ++stats_.collectives;
    int mine = int(send.size());
    std::vector<int> sizes(rank_ == 0 ? ranks_ : 0), displs;
    MPI_Gather(&mine, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, comm_->cart);
    std::vector<double> all;
    if (rank_ == 0) {
      displs.resize(ranks_);
      long total = 0;
      for (int r = 0; r < ranks_; ++r) {
        displs[r] = int(total);
        total += sizes[r];
      }
      all.resize(std::size_t(total));
    }
    MPI_Gatherv(send.data(), mine, MPI_DOUBLE, all.data(), sizes.data(), displs.data(),
                MPI_DOUBLE, 0, comm_->cart);
    if (counts) *counts = std::move(sizes);
    return all;
  }
#endif
  if (counts) *counts = {int(send.size())};
  return send;
}

void Decomposition::broadcast_vector(std::vector<double>& values) const {
  double size = double(values.size());
  broadcast(&size, 1);
  values.resize(std::size_t(size));
  if (!values.empty()) broadcast(values.data(), int(values.size()));
}

// --- Agreement after per-process file I/O (io/pvti.*, io/checkpoint.*) ---

std::string Decomposition::first_error(const std::string& mine, int* rank) const {
  if (rank) *rank = mine.empty() ? -1 : 0;
#ifdef CMCSURF_HAVE_MPI
  if (comm_) {
    const CommTimer timer(stats_.seconds);
    ++stats_.collectives;
    const int length = int(mine.size());
    std::vector<int> lengths(std::size_t(ranks_), 0);
    MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, comm_->cart);
    const auto first = std::find_if(lengths.begin(), lengths.end(), [](int l) { return l > 0; });
    if (rank) *rank = first == lengths.end() ? -1 : int(first - lengths.begin());
    if (first == lengths.end()) return "";
    const int root = int(first - lengths.begin());
    std::string message = rank_ == root ? mine : std::string(std::size_t(*first), ' ');
    MPI_Bcast(message.data(), *first, MPI_CHAR, root, comm_->cart);
    return message;
  }
#endif
  return mine;
}

void Decomposition::abort_all(int code) const {
#ifdef CMCSURF_HAVE_MPI
  if (comm_) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

#ifdef CMCSURF_HAVE_MPI
namespace {
bool several_processes() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) return false;
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  return ranks > 1;
}
}  // namespace
#endif

NodeGather allgather_on_node(const std::vector<std::uint64_t>& mine) {
  NodeGather g;
  g.values = mine;
#ifdef CMCSURF_HAVE_MPI
  if (!several_processes()) return g;
  MPI_Comm node = MPI_COMM_NULL;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  MPI_Comm_rank(node, &g.node_rank);
  MPI_Comm_size(node, &g.node_ranks);
  const int count = int(mine.size());
  g.values.resize(mine.size() * std::size_t(g.node_ranks));
  MPI_Allgather(mine.data(), count, MPI_UINT64_T, g.values.data(), count, MPI_UINT64_T, node);
  MPI_Comm_free(&node);
#endif
  return g;
}

std::vector<std::uint64_t> allgather_world(const std::vector<std::uint64_t>& mine) {
#ifdef CMCSURF_HAVE_MPI
  if (several_processes()) {
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    const int count = int(mine.size());
    std::vector<std::uint64_t> all(mine.size() * std::size_t(ranks));
    MPI_Allgather(mine.data(), count, MPI_UINT64_T, all.data(), count, MPI_UINT64_T,
                  MPI_COMM_WORLD);
    return all;
  }
#endif
  return mine;
}

// --- Process groups: a sweep's members side by side (docs/scaling.md) ---

void Decomposition::arrange(const Comm& processes) {
#ifdef CMCSURF_HAVE_MPI
  MPI_Comm_size(processes.cart, &ranks_);
  int cart_dims[3] = {0, 0, 0};  // MPI order: z (largest), y, x
  MPI_Dims_create(ranks_, 3, cart_dims);
  const int periodic[3] = {1, 1, 1};
  comm_ = std::make_shared<Comm>();
  MPI_Cart_create(processes.cart, 3, cart_dims, periodic, 0, &comm_->cart);
  MPI_Comm_rank(comm_->cart, &rank_);
  for (int a = 0; a < 3; ++a) dims_[a] = cart_dims[2 - a];
  coords_ = coords_of(rank_);
  for (int a = 0; a < 3; ++a) {
    int lo = 0, hi = 0;
    MPI_Cart_shift(comm_->cart, 2 - a, 1, &lo, &hi);
    neighbours_[a] = {lo, hi};
  }
#else
  (void)processes;
#endif
}

ProcessGroup Decomposition::split(int groups) {
  const auto world = Decomposition::world();
  if (groups < 1 || world->ranks() % groups != 0)
    throw std::invalid_argument(fmt::format("Decomposition::split: {} groups of {} processes",
                                            groups, world->ranks()));
  ProcessGroup g;
  g.groups = groups;
  const int size = world->ranks() / groups;
  g.index = world->rank() / size;  // world()'s rank is the MPI_COMM_WORLD rank (no reordering)
  g.decomposition = groups == 1 ? world : self();
#ifdef CMCSURF_HAVE_MPI
  if (groups > 1 && size > 1) {
    auto d = std::make_shared<Decomposition>();
    Comm members;  // freed once the group's process grid is laid over it
    MPI_Comm_split(MPI_COMM_WORLD, g.index, world->rank(), &members.cart);
    d->arrange(members);
    g.decomposition = d;
  }
#endif
  return g;
}

std::string Decomposition::check_grid_for(int ranks, int n) {
  std::array<int, 3> dims{1, 1, 1};
  if (ranks > 1) {
#ifdef CMCSURF_HAVE_MPI
    int cart_dims[3] = {0, 0, 0};
    MPI_Dims_create(ranks, 3, cart_dims);
    for (int a = 0; a < 3; ++a) dims[a] = cart_dims[2 - a];
#else
    throw std::logic_error("Decomposition::check_grid_for: several processes need MPI");
#endif
  }
  return grid_problem(dims, ranks, n);
}

std::vector<std::string> gather_world_bytes(const std::string& mine) {
#ifdef CMCSURF_HAVE_MPI
  if (several_processes()) {
    int ranks = 1, rank = 0;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (mine.size() > std::size_t(std::numeric_limits<int>::max()))
      throw std::length_error("gather_world_bytes: more than 2 GiB from one process");
    const int length = int(mine.size());
    std::vector<int> lengths(std::size_t(ranks), 0), displs(std::size_t(ranks), 0);
    // The lengths first, without spinning: rank 0 may wait here for groups still computing.
    MPI_Request request;
    MPI_Igather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD, &request);
    for (int done = 0;;) {
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
      if (done) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    long long total = 0;
    for (int r = 0; r < ranks; ++r) {
      displs[std::size_t(r)] = int(total);
      total += lengths[std::size_t(r)];
      if (rank == 0 && total > std::numeric_limits<int>::max())
        throw std::length_error("gather_world_bytes: more than 2 GiB in all");
    }
    std::string all(rank == 0 ? std::size_t(total) : 0, '\0');
    MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), displs.data(),
                MPI_CHAR, 0, MPI_COMM_WORLD);
    std::vector<std::string> out;
    if (rank == 0)
      for (int r = 0; r < ranks; ++r)
        out.push_back(all.substr(std::size_t(displs[std::size_t(r)]),
                                 std::size_t(lengths[std::size_t(r)])));
    return out;
  }
#endif
  return {mine};
}

ParallelSession::ParallelSession(int* argc, char*** argv) {
#ifdef CMCSURF_HAVE_MPI
  // Only the main thread calls MPI (OpenMP regions never do).
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
#else
  (void)argc;
  (void)argv;
#endif
}

ParallelSession::~ParallelSession() {
#ifdef CMCSURF_HAVE_MPI
  MPI_Finalize();
#endif
}

}  // namespace cmcsurf
