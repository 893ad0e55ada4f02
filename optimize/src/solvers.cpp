#include "solvers.hpp"

#include <algorithm>
#include <cmath>
#include <pagmo/algorithms/bee_colony.hpp>
#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/algorithms/de.hpp>
#include <pagmo/algorithms/de1220.hpp>
#include <pagmo/algorithms/gaco.hpp>
#include <pagmo/algorithms/gwo.hpp>
#include <pagmo/algorithms/pso.hpp>
#include <pagmo/algorithms/pso_gen.hpp>
#include <pagmo/algorithms/sade.hpp>
#include <pagmo/algorithms/sga.hpp>
#include <pagmo/algorithms/simulated_annealing.hpp>
#include <pagmo/algorithms/xnes.hpp>
#include <pagmo/batch_evaluators/member_bfe.hpp>
#include <pagmo/bfe.hpp>
#include <sstream>

#include "camplace/core/error.hpp"
#include "camplace/optimize/optimizer.hpp"

namespace camplace::optimize {
namespace {

struct Entry {
  const char* name;
  const char* pagmo_name;
  bool batch;
  unsigned min_population;
  const char* note;
};

// Every solver runs one generation per evolve() call with its memory switched on, so the
// optimizer can check the stop criteria between generations without resetting the solver.
constexpr Entry kSolvers[] = {
    {"gaco", "gaco", true, 8, "extended ant colony (Schlueter et al.), default"},
    {"cmaes", "cmaes", false, 5, "covariance matrix adaptation ES"},
    {"sade", "sade", false, 7, "self-adaptive differential evolution (jDE)"},
    {"de", "de", false, 5, "differential evolution rand/1/exp"},
    {"de1220", "de1220", false, 7, "self-adaptive DE over 18 variants"},
    {"pso", "pso", false, 2, "particle swarm (pagmo pso)"},
    {"pso_gen", "pso_gen", true, 2, "generational particle swarm"},
    {"simulated_annealing", "simulated_annealing", false, 1,
     "re-annealing from the best point (Corana)"},
    {"abc", "bee_colony", false, 2, "artificial bee colony"},
    {"gwo", "gwo", false, 3, "grey wolf optimizer"},
    {"sga", "sga", false, 2, "simple genetic algorithm"},
    {"xnes", "xnes", false, 5, "exponential natural evolution strategies"},
};

const Entry* find_entry(const std::string& name) {
  for (const Entry& e : kSolvers) {
    if (name == e.name) return &e;
  }
  return nullptr;
}

unsigned default_population(const std::string& name, std::size_t dimension) {
  if (name == "gaco") return 32;
  if (name == "cmaes" || name == "xnes") {
    return 4 + static_cast<unsigned>(3.0 * std::log(static_cast<double>(dimension)));
  }
  if (name == "simulated_annealing") return 1;
  return 20;
}

}  // namespace

const std::vector<std::string>& algorithm_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const Entry& e : kSolvers) v.emplace_back(e.name);
    return v;
  }();
  return names;
}

std::string algorithm_help() {
  std::ostringstream out;
  for (const Entry& e : kSolvers) {
    out << "  " << e.name << ": " << e.note << " (pagmo " << e.pagmo_name << ", "
        << (e.batch ? "parallel batch evaluation" : "sequential evaluation") << ")\n";
  }
  return out.str();
}

namespace detail {

Solver make_solver(const std::string& name, unsigned seed, int population, std::size_t dimension) {
  const Entry* entry = find_entry(name);
  if (entry == nullptr) {
    std::string names;
    for (const Entry& e : kSolvers) names += std::string(names.empty() ? "" : ", ") + e.name;
    throw core::OptionError("algorithm", "unknown solver '" + name + "' (one of: " + names + ")");
  }
  if (population < 0) {
    throw core::OptionError("population", "must not be negative");
  }
  const unsigned pop =
      population > 0 ? static_cast<unsigned>(population) : default_population(name, dimension);
  if (pop < entry->min_population) {
    throw core::OptionError("population", name + " needs a population of at least " +
                                              std::to_string(entry->min_population));
  }

  Solver solver;
  solver.population = pop;
  solver.batch = entry->batch;
  if (name == "gaco") {
    // Kernel (solution archive) as large as the population; acc (minimum penalty spacing in
    // the archive) well below the Err tolerance so the archive can concentrate near it.
    pagmo::gaco algo(1u, pop, 1.0, 0.0, 1e-4, 1u, 7u, 100000u, 100000u, 0.0, true, seed);
    algo.set_bfe(pagmo::bfe{pagmo::member_bfe{}});
    solver.algorithm = pagmo::algorithm{algo};
  } else if (name == "cmaes") {
    solver.algorithm =
        pagmo::algorithm{pagmo::cmaes(1u, -1, -1, -1, -1, 0.5, 1e-9, 1e-9, true, true, seed)};
  } else if (name == "sade") {
    solver.algorithm = pagmo::algorithm{pagmo::sade(1u, 2u, 1u, 1e-9, 1e-9, true, seed)};
  } else if (name == "de") {
    solver.algorithm = pagmo::algorithm{pagmo::de(1u, 0.8, 0.9, 2u, 1e-9, 1e-9, seed)};
  } else if (name == "de1220") {
    solver.algorithm = pagmo::algorithm{pagmo::de1220(
        1u, pagmo::de1220_statics<void>::allowed_variants, 1u, 1e-9, 1e-9, true, seed)};
  } else if (name == "pso") {
    solver.algorithm =
        pagmo::algorithm{pagmo::pso(1u, 0.7298, 2.05, 2.05, 0.5, 5u, 2u, 4u, true, seed)};
  } else if (name == "pso_gen") {
    pagmo::pso_gen algo(1u, 0.7298, 2.05, 2.05, 0.5, 5u, 2u, 4u, true, seed);
    algo.set_bfe(pagmo::bfe{pagmo::member_bfe{}});
    solver.algorithm = pagmo::algorithm{algo};
  } else if (name == "simulated_annealing") {
    // Temperatures on the scale of Err (m²); one annealing cycle per evolve() call, each
    // starting from the best point found so far.
    solver.algorithm =
        pagmo::algorithm{pagmo::simulated_annealing(1.0, 1e-3, 10u, 1u, 10u, 1.0, seed)};
  } else if (name == "abc") {
    solver.algorithm = pagmo::algorithm{pagmo::bee_colony(1u, 20u, seed)};
  } else if (name == "gwo") {
    // gwo's schedule depends on its generation count; 50 generations per call.
    solver.algorithm = pagmo::algorithm{pagmo::gwo(50u, seed)};
  } else if (name == "sga") {
    solver.algorithm = pagmo::algorithm{
        pagmo::sga(1u, 0.9, 1.0, 0.02, 1.0, 2u, "exponential", "polynomial", "tournament", seed)};
  } else if (name == "xnes") {
    solver.algorithm =
        pagmo::algorithm{pagmo::xnes(1u, -1, -1, -1, -1, 1e-9, 1e-9, true, true, seed)};
  }
  return solver;
}

}  // namespace detail
}  // namespace camplace::optimize
