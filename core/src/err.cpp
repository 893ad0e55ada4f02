#include "camplace/core/err.hpp"

#include <algorithm>

#include "camplace/core/evaluation.hpp"

namespace camplace::core {

double error_functional(const std::vector<ErrTerm>& terms) {
  // Err_{L,H} = Σ_h Σ_l ω_lh (d(C_h, O_u(a_lh)) − d(C_h, M(a_lh, e)))²  (SPEC §4).
  double sum = 0.0;
  for (const ErrTerm& t : terms) {
    const double diff = t.d_true - t.d_model;
    sum += t.weight * diff * diff;
  }
  return sum;
}

double error_of(const std::vector<StateResult>& states) {
  std::vector<ErrTerm> terms;
  terms.reserve(states.size());
  for (const StateResult& s : states) terms.push_back({s.weight, s.d_true, s.d_model});
  return error_functional(terms);
}

double lower_bound_threshold(double err_lower_bound) { return err_lower_bound * (1.0 + 1e-12); }

double success_target(bool conservative, double tolerance, double err_lower_bound) {
  return conservative ? std::max(tolerance, lower_bound_threshold(err_lower_bound)) : tolerance;
}

double default_tolerance(const Box3& area, const std::array<int, 3>& resolution) {
  const Vec3 step = area.size().cwiseQuotient(Vec3(resolution[0], resolution[1], resolution[2]));
  const double half_diagonal = 0.5 * step.norm();
  return half_diagonal * half_diagonal;
}

}  // namespace camplace::core
