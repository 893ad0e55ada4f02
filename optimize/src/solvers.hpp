#pragma once
// Private: the solver table (name → pagmo algorithm with camplace's settings).
#include <cstddef>
#include <pagmo/algorithm.hpp>
#include <string>

namespace camplace::optimize::detail {

struct Solver {
  pagmo::algorithm algorithm;
  unsigned population = 0;
  bool batch = false;  ///< evaluates each generation through a bfe (parallel)
};

/// The solver `name` (one of algorithm_names()) seeded with `seed`, for a decision vector of
/// `dimension` variables; population 0 takes the solver's default. Throws core::InputError.
Solver make_solver(const std::string& name, unsigned seed, int population, std::size_t dimension);

}  // namespace camplace::optimize::detail
