#include "host-sim/mpi/comm.h"

#include <mpi.h>
#include <pthread.h>
#include <signal.h>

#include <chrono>
#include <climits>
#include <cstdlib>
#include <ctime>
#include <stdexcept>
#include <thread>

namespace troupe::sim::mpi {
namespace {

// Times one MPI call into the total (wall s), and into `cpu` (this
// thread's CPU s: OpenMPI polls while it waits) when given.
class Timed {
 public:
  explicit Timed(double& total, double* cpu = nullptr)
      : total_(total), cpu_(cpu), start_(std::chrono::steady_clock::now()), start_cpu_(thread_cpu_s()) {}
  ~Timed() {
    total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (cpu_) *cpu_ += thread_cpu_s() - start_cpu_;
  }

 private:
  static double thread_cpu_s() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
  }
  double& total_;
  double* cpu_;
  std::chrono::steady_clock::time_point start_;
  double start_cpu_;
};

int checked_count(size_t n) {
  // MPI counts are ints: a share of 2 GiB is a world far beyond what one
  // step exchanges.
  if (n > size_t(INT_MAX)) throw std::length_error("more than 2 GiB for one MPI message");
  return int(n);
}

// Displacements of the counts, and their total.
int offsets(const std::vector<int>& counts, std::vector<int>& displs) {
  displs.resize(counts.size());
  size_t total = 0;
  for (size_t r = 0; r < counts.size(); ++r) {
    displs[r] = checked_count(total);
    total += size_t(counts[r]);
  }
  return checked_count(total);
}

void split(const std::vector<std::byte>& flat, const std::vector<int>& counts, const std::vector<int>& displs,
           std::vector<Bytes>& out) {
  out.assign(counts.size(), {});
  for (size_t r = 0; r < counts.size(); ++r)
    out[r].assign(flat.begin() + displs[r], flat.begin() + displs[r] + counts[r]);
}

}  // namespace

bool Comm::launched() {
  // mpirun (OpenMPI) sets these for every process it starts.
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

Comm::Comm(int* argc, char*** argv) {
  // mpirun stopped by SIGTERM or SIGINT passes SIGTERM on to every process
  // (and SIGKILL a second later). The run loop takes it from a signalfd
  // (troupe::StopOnSignal), which sees it only where it is blocked: in every
  // thread, MPI's own included, so before MPI_Init starts them. Otherwise
  // one of MPI's threads takes it and the process dies at once, the
  // leader's table and the followers' Stop order lost.
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  MPI_Init(argc, argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

Comm::~Comm() {
  MPI_Finalize();
}

void Comm::exchange(const std::vector<Bytes>& send, std::vector<Bytes>& recv) {
  Timed t(seconds_, &cpu_seconds_);
  std::vector<int> send_counts(static_cast<size_t>(size_)), recv_counts(static_cast<size_t>(size_)),
      send_displs, recv_displs;
  for (int r = 0; r < size_; ++r) {
    // Its own share stays here: the caller keeps what it sends itself.
    send_counts[size_t(r)] = r == rank_ ? 0 : checked_count(send[size_t(r)].size());
    if (r != rank_ && !send[size_t(r)].empty()) {
      bytes_sent_ += send[size_t(r)].size();
      ++messages_sent_;
    }
  }
  {
    Timed w(wait_seconds_);
    MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  }
  const int send_total = offsets(send_counts, send_displs);
  const int recv_total = offsets(recv_counts, recv_displs);
  std::vector<std::byte> out(size_t(send_total) + 1), in(size_t(recv_total) + 1);
  for (int r = 0; r < size_; ++r) {
    if (send_counts[size_t(r)] > 0)
      std::copy(send[size_t(r)].begin(), send[size_t(r)].end(), out.begin() + send_displs[size_t(r)]);
  }
  MPI_Alltoallv(out.data(), send_counts.data(), send_displs.data(), MPI_BYTE, in.data(), recv_counts.data(),
                recv_displs.data(), MPI_BYTE, MPI_COMM_WORLD);
  split(in, recv_counts, recv_displs, recv);
}

void Comm::all_gather(const Bytes& mine, std::vector<Bytes>& all) {
  Timed t(seconds_, &cpu_seconds_);
  const int count = checked_count(mine.size());
  std::vector<int> counts(static_cast<size_t>(size_)), displs;
  {
    Timed w(wait_seconds_);
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  }
  const int total = offsets(counts, displs);
  std::vector<std::byte> flat(size_t(total) + 1);
  MPI_Allgatherv(mine.data(), count, MPI_BYTE, flat.data(), counts.data(), displs.data(), MPI_BYTE,
                 MPI_COMM_WORLD);
  bytes_sent_ += mine.size() * size_t(size_ - 1);
  messages_sent_ += mine.empty() ? 0 : uint64_t(size_ - 1);
  split(flat, counts, displs, all);
}

void Comm::gather(const Bytes& mine, std::vector<Bytes>& all) {
  Timed t(seconds_, &cpu_seconds_);
  const int count = checked_count(mine.size());
  std::vector<int> counts(static_cast<size_t>(size_)), displs;
  {
    Timed w(wait_seconds_);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  }
  std::vector<std::byte> flat;
  if (rank_ == 0) flat.resize(size_t(offsets(counts, displs)) + 1);
  MPI_Gatherv(mine.data(), count, MPI_BYTE, flat.data(), counts.data(), displs.data(), MPI_BYTE, 0,
              MPI_COMM_WORLD);
  if (rank_ != 0) {
    bytes_sent_ += mine.size();
    messages_sent_ += mine.empty() ? 0 : 1;
    all.clear();
    return;
  }
  split(flat, counts, displs, all);
}

void Comm::broadcast(Bytes& bytes) {
  Timed t(seconds_, &cpu_seconds_);
  uint64_t size = bytes.size();
  {
    Timed w(wait_seconds_);  // the size's broadcast: the followers wait for the leader here
    MPI_Request request;
    MPI_Ibcast(&size, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &request);
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    while (!done) {
      // A leader that steps answers within a step; one that is paused or
      // serving may take seconds. 0.1 ms is well below a step's time.
      std::this_thread::sleep_for(std::chrono::microseconds(100));
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    }
  }
  if (rank_ != 0) bytes.resize(size);
  if (rank_ == 0) {
    bytes_sent_ += bytes.size() * size_t(size_ - 1);
    messages_sent_ += uint64_t(size_ - 1);
  }
  MPI_Bcast(bytes.data(), checked_count(bytes.size()), MPI_BYTE, 0, MPI_COMM_WORLD);
}

bool Comm::any(bool mine) {
  Timed t(seconds_, &cpu_seconds_), w(wait_seconds_);  // one int: all of it is waiting
  int in = mine ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return out != 0;
}

void Comm::abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

}  // namespace troupe::sim::mpi
