#pragma once
/// Work spread over the ranks of an MPI job: `mpirun -n N camplace study|validate`.
/// Rank 0 plans the work, hands out one item at a time to every rank (itself included) as each
/// asks, and collects the results; the other ranks carry out what they are given. Everything
/// polls (MPI_Iprobe, the task's poll, a 2 ms sleep), so no rank spins a core while it waits
/// and rank 0 works besides handing out. Only the main thread calls MPI (MPI_THREAD_FUNNELED).
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace camplace::jobs::mpi {

/// True when this process was started by mpirun or srun (Open MPI's or PMI's environment),
/// i.e. when MPI is to be initialised. A camplace started otherwise never touches MPI.
bool launched_by_mpirun();

/// True when camplace was built with MPI (CAMPLACE_WITH_MPI and an MPI library found).
bool built_with_mpi();

/// MPI for the lifetime of a command: MPI_Init_thread and MPI_Finalize. On rank 0 the
/// destructor first releases any rank still waiting for work (rank 0 may end with an error
/// before it handed anything out). In a build without MPI a job of one rank is rank 0 of 1, and
/// a job of more ranks throws std::runtime_error ("camplace was built without MPI ...").
class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
};

/// One item of work under way on a rank.
class Task {
 public:
  virtual ~Task() = default;
  /// The result once the work is done (a text the caller defines), nothing while it goes on.
  virtual std::optional<std::string> poll() = 0;
};

/// What rank 0 does with a result.
enum class Verdict {
  done,   ///< the item is finished
  retry,  ///< hand the item out again, to another rank if one is free
  stop,   ///< the item is finished; hand out nothing more (an error, an interrupt)
};

struct Handlers {
  /// Starts an item's work from its payload without waiting for it (every rank).
  std::function<std::unique_ptr<Task>(const std::string& payload)> start;
  /// Rank 0: what a result means (item: index into the payloads).
  std::function<Verdict(std::size_t item, int rank, const std::string& result)> judge;
  /// Rank 0: called as an item is handed to a rank.
  std::function<void(std::size_t item, int rank)> on_assign;
  /// Set (a signal): rank 0 hands out nothing more and waits for the items under way.
  const std::atomic<bool>* interrupt = nullptr;
};

/// Rank 0: carries out the items (payloads, handed out in this order) on every rank of the
/// session and returns each item's last result by index; an item never started has none.
/// Without MPI (built_with_mpi() false) distribute and serve throw std::runtime_error.
std::vector<std::optional<std::string>> distribute(const Session& session,
                                                   const std::vector<std::string>& payloads,
                                                   const Handlers& handlers);

/// Ranks > 0: asks rank 0 for work and carries it out until rank 0 says stop.
void serve(const Session& session, const Handlers& handlers);

}  // namespace camplace::jobs::mpi
