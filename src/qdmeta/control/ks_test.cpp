#include "qdmeta/control/ks_test.hpp"

#include <algorithm>
#include <cmath>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

double ks_statistic(std::span<const double> a, std::span<const double> b) {
  if (a.empty() || b.empty()) throw Error("ks_statistic: both samples must be non-empty");
  const double n = static_cast<double>(a.size());
  const double m = static_cast<double>(b.size());
  std::size_t i = 0, j = 0;
  double largest = 0.0;
  // Walk the merged order; at each distinct value both distribution functions have stepped
  // past every copy of it, so ties are handled exactly.
  while (i < a.size() && j < b.size()) {
    const double x = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= x) ++i;
    while (j < b.size() && b[j] <= x) ++j;
    largest = std::max(largest, std::abs(static_cast<double>(i) / n - static_cast<double>(j) / m));
  }
  return largest;
}

double ks_critical_value(std::size_t n, std::size_t m, double alpha) {
  if (n == 0 || m == 0) throw Error("ks_critical_value: both samples must be non-empty");
  if (!(alpha > 0.0 && alpha < 1.0)) throw Error("ks_critical_value: alpha must be in (0, 1)");
  const double c = std::sqrt(-std::log(alpha / 2.0) / 2.0);
  const auto dn = static_cast<double>(n), dm = static_cast<double>(m);
  return c * std::sqrt((dn + dm) / (dn * dm));
}

}  // namespace qdmeta
