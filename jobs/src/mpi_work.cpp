// Work spread over MPI ranks: rank 0 hands out items one at a time as ranks ask;
// every rank polls, so none spins a core while it waits.
#include "camplace/jobs/mpi_work.hpp"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <stdexcept>
#include <thread>

namespace camplace::jobs::mpi {

namespace {

// Messages: a worker says it is ready, rank 0 sends work ("<item>\n<payload>"), the worker
// sends its result ("<item>\n<result>"), rank 0 says stop.
enum Tag : int { kReady = 1, kResult = 2, kWork = 3, kStop = 4 };

// Rank 0 has told the other ranks to stop (Session's destructor does it otherwise).
bool g_released = false;

void pause() { std::this_thread::sleep_for(std::chrono::milliseconds(2)); }

void send(int rank, Tag tag, const std::string& text) {
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, rank, tag, MPI_COMM_WORLD);
}

/// The message `status` announced (MPI_Iprobe), received.
std::string receive(const MPI_Status& status) {
  int count = 0;
  MPI_Get_count(&status, MPI_CHAR, &count);
  std::string text(static_cast<std::size_t>(count), '\0');
  MPI_Recv(text.data(), count, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return text;
}

/// "<item>\n<text>" split.
std::pair<std::size_t, std::string> split_item(const std::string& message) {
  const std::size_t newline = message.find('\n');
  if (newline == std::string::npos) throw std::runtime_error("MPI: a malformed message");
  return {std::stoul(message.substr(0, newline)), message.substr(newline + 1)};
}

void release_workers(int size) {
  for (int r = 1; r < size; ++r) send(r, kStop, "");
  g_released = true;
}

}  // namespace

bool built_with_mpi() { return true; }

bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

Session::Session() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

Session::~Session() {
  if (rank_ == 0 && !g_released) release_workers(size_);
  MPI_Finalize();
}

std::vector<std::optional<std::string>> distribute(const Session& session,
                                                   const std::vector<std::string>& payloads,
                                                   const Handlers& handlers) {
  const int size = session.size();
  std::vector<std::optional<std::string>> results(payloads.size());
  std::deque<std::size_t> queue;
  for (std::size_t i = 0; i < payloads.size(); ++i) queue.push_back(i);
  // The rank an item last failed on (a retry goes to another rank if one is free).
  std::vector<int> failed_on(payloads.size(), -1);
  constexpr long kIdle = -1, kNotReady = -2;
  std::vector<long> busy(static_cast<std::size_t>(size), kNotReady);  // item per rank
  busy[0] = kIdle;
  std::unique_ptr<Task> own;
  bool stopping = false;
  // Rank 0's own cost per item: from a result taken in to the rank's next item sent (measured,
  // printed at the end; the polls add at most 2 ms at each end besides).
  using Clock = std::chrono::steady_clock;
  std::vector<std::optional<Clock::time_point>> result_at(static_cast<std::size_t>(size));
  Clock::duration handling{};
  int handled = 0;

  auto handle = [&](int rank, std::size_t item, std::string result) {
    const Verdict verdict = handlers.judge(item, rank, result);
    results[item] = std::move(result);
    if (verdict == Verdict::retry && !stopping) {
      failed_on[item] = rank;
      queue.push_front(item);  // it was among the longest left
    }
    if (verdict == Verdict::stop) stopping = true;
  };
  auto pick = [&](int rank) {
    for (auto it = queue.begin(); it != queue.end(); ++it) {
      if (failed_on[*it] != rank) {
        const std::size_t item = *it;
        queue.erase(it);
        return item;
      }
    }
    const std::size_t item = queue.front();
    queue.pop_front();
    return item;
  };

  for (;;) {
    bool progressed = false;
    if (own) {
      if (std::optional<std::string> result = own->poll()) {
        result_at[0] = Clock::now();
        own.reset();
        handle(0, static_cast<std::size_t>(busy[0]), std::move(*result));
        busy[0] = kIdle;
        progressed = true;
      }
    }
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
    if (arrived) {
      result_at[static_cast<std::size_t>(status.MPI_SOURCE)] = Clock::now();
      const std::string message = receive(status);
      if (status.MPI_TAG == kResult) {
        auto [item, result] = split_item(message);
        handle(status.MPI_SOURCE, item, std::move(result));
      }
      busy[static_cast<std::size_t>(status.MPI_SOURCE)] = kIdle;
      progressed = true;
    }
    if (handlers.interrupt != nullptr && handlers.interrupt->load()) stopping = true;
    for (int r = 0; r < size && !stopping && !queue.empty(); ++r) {
      if (busy[static_cast<std::size_t>(r)] != kIdle) continue;
      const std::size_t item = pick(r);
      if (handlers.on_assign) handlers.on_assign(item, r);
      if (r == 0) {
        own = handlers.start(payloads[item]);
      } else {
        send(r, kWork, std::to_string(item) + "\n" + payloads[item]);
      }
      busy[static_cast<std::size_t>(r)] = static_cast<long>(item);
      progressed = true;
      if (result_at[static_cast<std::size_t>(r)]) {
        handling += Clock::now() - *result_at[static_cast<std::size_t>(r)];
        ++handled;
        result_at[static_cast<std::size_t>(r)].reset();
      }
    }
    bool under_way = false;
    for (long b : busy) under_way = under_way || b >= 0;
    if (!under_way && (stopping || queue.empty())) break;
    if (!progressed) pause();
  }
  release_workers(size);
  if (handled > 0) {
    std::fprintf(stderr,
                 "mpi: %zu items on %d ranks; rank 0 took %.3f ms from a result to the next item\n",
                 payloads.size(), size,
                 std::chrono::duration<double, std::milli>(handling).count() / handled);
  }
  return results;
}

void serve(const Session&, const Handlers& handlers) {
  send(0, kReady, "");
  for (;;) {
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
    if (!arrived) {
      pause();
      continue;
    }
    const std::string message = receive(status);
    if (status.MPI_TAG == kStop) return;
    auto [item, payload] = split_item(message);
    std::unique_ptr<Task> task = handlers.start(payload);
    std::optional<std::string> result;
    while (!(result = task->poll())) pause();
    send(0, kResult, std::to_string(item) + "\n" + *result);
  }
}

}  // namespace camplace::jobs::mpi
