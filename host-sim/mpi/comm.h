// A thin C++ layer over the few MPI calls a divided world needs: byte
// buffers to every other process and back, gathers to the first process,
// and agreement on a flag. Counts what it sends and how long it waits, so
// benchmarks can tell communication from computation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace troupe::sim::mpi {

using Bytes = std::vector<std::byte>;

class Comm {
 public:
  /// True when this process was started by mpirun (its environment says
  /// so): only then does troupe-sim divide its world.
  static bool launched();

  /// MPI_Init; the destructor calls MPI_Finalize.
  Comm(int* argc, char*** argv);
  ~Comm();
  Comm(const Comm&) = delete;
  Comm& operator=(const Comm&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  /// Sends send[r] to every rank r (send.size() == size(); its own is not
  /// sent) and receives rank r's bytes for this one into recv[r].
  void exchange(const std::vector<Bytes>& send, std::vector<Bytes>& recv);
  /// Every rank's `mine`, into all[r] on every rank.
  void all_gather(const Bytes& mine, std::vector<Bytes>& all);
  /// Every rank's `mine`, into all[r] on rank 0 (all is left empty
  /// elsewhere).
  void gather(const Bytes& mine, std::vector<Bytes>& all);
  /// Rank 0's `bytes` into `bytes` on every rank. The others wait asleep
  /// between looks, not spinning: a paused leader costs them no CPU.
  void broadcast(Bytes& bytes);
  /// True on every rank when `mine` is true on any.
  bool any(bool mine);
  /// Ends every process of the run at once, with `code`.
  [[noreturn]] void abort(int code);

  /// What this rank sent to others (its own share excluded), bytes, and
  /// in how many messages (empty sends not counted).
  uint64_t bytes_sent() const { return bytes_sent_; }
  uint64_t messages_sent() const { return messages_sent_; }
  /// Wall time spent inside MPI calls, s: waiting for the slowest rank
  /// counts here.
  double seconds() const { return seconds_; }
  /// The part of seconds() spent agreeing on sizes before the data moves
  /// (a few bytes each way, s): mostly waiting for the slowest rank to
  /// arrive, so seconds() - wait_seconds() is the data's transfer.
  double wait_seconds() const { return wait_seconds_; }
  /// CPU time of the calling thread inside MPI calls, s: OpenMPI polls
  /// while it waits, so a process's CPU time less this is its own work.
  double cpu_seconds() const { return cpu_seconds_; }

 private:
  int rank_ = 0, size_ = 1;
  uint64_t bytes_sent_ = 0, messages_sent_ = 0;
  double seconds_ = 0;
  double wait_seconds_ = 0;
  double cpu_seconds_ = 0;
};

}  // namespace troupe::sim::mpi
