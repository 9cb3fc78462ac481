// Prints the bits of a CMA-ES run at QD-Meta's size (222 meta-genes, lambda = 10, 80
// generations, 16 eigendecompositions) in hexadecimal. tests/CMakeLists.txt builds it twice,
// once for the x86-64 baseline (SSE2, no FMA) and once for this machine (-march=native, with
// AVX2 or AVX-512 and FMA), from CMA-ES's own sources, and requires the same output: CMA-ES's
// bits, and so QD-Meta's results, must not depend on the CPU.
#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/meta/cma_es.hpp"

namespace {

// FNV-1a over the bytes of a matrix.
std::uint64_t fingerprint(const Eigen::MatrixXd& m) {
  std::uint64_t hash = 1469598103934665603ULL;
  const auto* bytes = reinterpret_cast<const unsigned char*>(m.data());
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.size()) * sizeof(double); ++i) {
    hash = (hash ^ bytes[i]) * 1099511628211ULL;
  }
  return hash;
}

// A weighted sphere, summed in a fixed order (this file, too, is compiled without contraction).
double weighted_sphere(const double* x, int n) {
  double f = 0.0;
  for (int i = 0; i < n; ++i) f += static_cast<double>(i + 1) * (x[i] - 0.25) * (x[i] - 0.25);
  return f;
}

}  // namespace

int main() {
  qdmeta::CmaEsParams params;
  params.dimension = 222;
  params.population_size = 10;
  qdmeta::CmaEs cma(params);
  qdmeta::Rng rng(2024);
  Eigen::VectorXd fitness(params.population_size);
  for (int g = 0; g < 80; ++g) {
    const Eigen::MatrixXd& x = cma.ask(rng);
    for (int k = 0; k < params.population_size; ++k) fitness(k) = weighted_sphere(&x(0, k), params.dimension);
    cma.tell(fitness, qdmeta::CmaObjective::kMinimise);
  }
  const qdmeta::CmaEsState& s = cma.state();
  std::printf("decompositions %" PRId64 "\nsigma %a\n", s.decompositions, s.sigma);
  std::printf("mean %016" PRIx64 "\nC %016" PRIx64 "\nB %016" PRIx64 "\nD %016" PRIx64 "\n", fingerprint(s.mean),
              fingerprint(s.C), fingerprint(s.B), fingerprint(s.D));
  std::printf("p_sigma %016" PRIx64 "\np_c %016" PRIx64 "\n", fingerprint(s.p_sigma), fingerprint(s.p_c));
  std::printf("next sample %016" PRIx64 "\n", fingerprint(cma.ask(rng)));
  return 0;
}
