#include "optim/search/nelder_mead.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace rangecal {

NelderMeadResult nelder_mead(const std::function<double(const Eigen::VectorXd&)>& f,
                             const Eigen::VectorXd& x0, const Eigen::VectorXd& step, double tolerance,
                             int max_evaluations) {
  const Eigen::Index n = x0.size();
  NelderMeadResult out;
  std::vector<Eigen::VectorXd> x(static_cast<std::size_t>(n + 1), x0);
  std::vector<double> v(static_cast<std::size_t>(n + 1));
  auto eval = [&](const Eigen::VectorXd& p) {
    ++out.evaluations;
    return f(p);
  };
  for (Eigen::Index i = 0; i < n; ++i) x[static_cast<std::size_t>(i + 1)][i] += step[i];
  for (std::size_t i = 0; i < x.size(); ++i) v[i] = eval(x[i]);
  std::vector<std::size_t> order(x.size());
  while (true) {
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
    const std::size_t best = order.front(), worst = order.back(), second = order[order.size() - 2];
    if (!(v[worst] - v[best] > tolerance) || out.evaluations >= max_evaluations) {
      out.x = x[best], out.value = v[best];
      return out;
    }
    Eigen::VectorXd centre = Eigen::VectorXd::Zero(n);
    for (std::size_t i : order)
      if (i != worst) centre += x[i] / static_cast<double>(n);
    const Eigen::VectorXd reflected = centre + (centre - x[worst]);
    const double vr = eval(reflected);
    if (vr < v[best]) {
      const Eigen::VectorXd expanded = centre + 2 * (centre - x[worst]);
      const double ve = eval(expanded);
      if (ve < vr)
        x[worst] = expanded, v[worst] = ve;
      else
        x[worst] = reflected, v[worst] = vr;
      continue;
    }
    if (vr < v[second]) {
      x[worst] = reflected, v[worst] = vr;
      continue;
    }
    // Contract outside (towards the reflection) or inside (towards the worst point).
    const bool outside = vr < v[worst];
    const Eigen::VectorXd contracted = outside ? Eigen::VectorXd(centre + 0.5 * (reflected - centre))
                                               : Eigen::VectorXd(centre + 0.5 * (x[worst] - centre));
    const double vc = eval(contracted);
    if (vc < (outside ? vr : v[worst])) {
      x[worst] = contracted, v[worst] = vc;
      continue;
    }
    for (std::size_t i : order) {  // shrink towards the best
      if (i == best) continue;
      x[i] = x[best] + 0.5 * (x[i] - x[best]);
      v[i] = eval(x[i]);
    }
  }
}

}  // namespace rangecal
