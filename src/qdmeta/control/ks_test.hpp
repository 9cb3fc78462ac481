#pragma once
// The two-sample Kolmogorov-Smirnov test, as the state tree uses it to decide whether the
// values on either side of a candidate threshold come from different distributions.
#include <cstddef>
#include <span>

namespace qdmeta {

// sup_x |F_a(x) - F_b(x)| of the two empirical distribution functions. Both samples must be
// sorted ascending and non-empty.
double ks_statistic(std::span<const double> sorted_a, std::span<const double> sorted_b);

// The large-sample critical value c(alpha) sqrt((n + m) / (n m)), c(alpha) = sqrt(-ln(alpha/2) / 2)
// (1.358 at alpha = 0.05). The samples differ at level alpha when the statistic exceeds it.
double ks_critical_value(std::size_t n, std::size_t m, double alpha);

}  // namespace qdmeta
