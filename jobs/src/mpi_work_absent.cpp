// A build without MPI: a job of one rank needs none; more ranks get a clear error.
#include <cstdlib>
#include <initializer_list>
#include <stdexcept>
#include <string>

#include "camplace/jobs/mpi_work.hpp"

namespace camplace::jobs::mpi {

namespace {

[[noreturn]] void built_without_mpi() {
  throw std::runtime_error(
      "camplace was built without MPI, so it cannot spread its work over the ranks of an MPI "
      "job (reconfigure with -DCAMPLACE_WITH_MPI=ON and install libopenmpi-dev), or run it "
      "without mpirun");
}

/// The number in the first of `names` set in the environment, or `otherwise`.
long environment_number(std::initializer_list<const char*> names, long otherwise) {
  for (const char* name : names) {
    if (const char* value = std::getenv(name)) return std::strtol(value, nullptr, 10);
  }
  return otherwise;
}

}  // namespace

bool built_with_mpi() { return false; }

bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

Session::Session() {
  const long rank = environment_number({"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}, 0);
  const long size = environment_number({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}, 1);
  if (rank != 0 || size > 1) built_without_mpi();
}

Session::~Session() = default;

std::vector<std::optional<std::string>> distribute(const Session&, const std::vector<std::string>&,
                                                   const Handlers&) {
  built_without_mpi();
}

void serve(const Session&, const Handlers&) { built_without_mpi(); }

}  // namespace camplace::jobs::mpi
