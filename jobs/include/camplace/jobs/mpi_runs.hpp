#pragma once
/// Child processes (process.hpp) spread over the ranks of an MPI job (mpi_work.hpp): what
/// `mpirun -n N camplace study` does with the study's runs, and the messages it sends for them.
#include <string>
#include <vector>

#include "camplace/jobs/mpi_work.hpp"
#include "camplace/jobs/process.hpp"

namespace camplace::jobs::mpi {

/// A process to run on some rank.
struct RankRun {
  ProcessLaunch launch;  ///< started as `PROGRAM ARGS` by the rank's own program
  std::string run_file;  ///< removed before a killed run is handed out again
  std::string label;     ///< "<group> seed <seed>", for messages
};

/// Rank 0: carries out the runs on every rank of the session (itself included), each as
/// run_process does it, and returns each run's outcome by index. A run whose process died of a
/// signal its rank did not get is handed out again (three attempts); a signal to a rank stops
/// the job after the runs under way. A run never started counts as interrupted. Progress lines
/// on stderr begin with `name` ("study: <label> on rank 2 (3 of 8 to run)").
std::vector<ProcessOutcome> run_on_ranks(const Session& session, const std::string& program,
                                         const std::vector<RankRun>& runs, const std::string& name);

/// Ranks > 0: carries out the runs rank 0 hands out with `program` until rank 0 says stop.
void serve_runs(const Session& session, const std::string& program);

/// A launch as an MPI payload: the output file, then the arguments, '\0' between them.
std::string encode_launch(const ProcessLaunch& launch);
ProcessLaunch decode_launch(const std::string& payload);
/// An outcome as an MPI result: whether the rank had a signal, whether the run was interrupted
/// ('1'/'0' each), then ProcessOutcome::failure.
std::string encode_outcome(const ProcessOutcome& outcome, bool rank_signalled);

}  // namespace camplace::jobs::mpi
