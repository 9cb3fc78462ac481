#pragma once
// Seeded random streams. Every stochastic component takes an Rng; streams are derived from
// (seed, keys...) by hashing, never from a thread id, so results do not depend on scheduling.
#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <utility>
#include <vector>

#include "qdmeta/core/fused.hpp"

namespace qdmeta {

// SplitMix64 finaliser: a bijective 64-bit mixer, used to seed and to derive streams.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// xoshiro256++ (Blackman & Vigna): fast, 256-bit state, passes BigCrush.
class Rng {
 public:
  using result_type = std::uint64_t;
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return std::numeric_limits<result_type>::max(); }

  explicit Rng(std::uint64_t seed = 0) { reseed(seed); }

  // An independent stream for (seed, keys...), e.g. (seed, kMutation, generation, chunk).
  static Rng stream(std::uint64_t seed, std::initializer_list<std::uint64_t> keys) {
    std::uint64_t h = mix64(seed);
    for (std::uint64_t k : keys) h = mix64(h ^ mix64(k + 0x632BE59BD9B4E019ULL));
    return Rng(h);
  }

  void reseed(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& s : state_) {
      x += 0x9E3779B97F4A7C15ULL;
      s = mix64(x);
    }
  }

  result_type operator()() {
    const std::uint64_t result = rotl(state_[0] + state_[3], 23) + state_[0];
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotl(state_[3], 45);
    return result;
  }

  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>((*this)() >> 11) * 0x1.0p-53; }
  // Uniform in (0, 1]: safe to take the logarithm of.
  double uniform_open0() { return static_cast<double>(((*this)() >> 11) + 1) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  // Uniform integer in [0, n), unbiased (Lemire's multiply-and-reject). n must be > 0.
  std::uint64_t below(std::uint64_t n) {
    __uint128_t m = static_cast<__uint128_t>((*this)()) * n;
    auto low = static_cast<std::uint64_t>(m);
    if (low < n) {
      const std::uint64_t threshold = (0 - n) % n;
      while (low < threshold) {
        m = static_cast<__uint128_t>((*this)()) * n;
        low = static_cast<std::uint64_t>(m);
      }
    }
    return static_cast<std::uint64_t>(m >> 64);
  }

  // Standard normal by the polar Box-Muller method; the second variate is cached.
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform() - 1.0;
      v = 2.0 * uniform() - 1.0;
      // The fused form GCC contracts u * u + v * v to on an FMA machine, written out so that the
      // bits do not depend on the compiling file's -ffp-contract or on the CPU (CMA-ES's file
      // is compiled without contraction).
      s = std::fma(u, u, v * v);
    } while (s >= 1.0 || s == 0.0);
    const double factor = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * factor;
    has_spare_ = true;
    return u * factor;
  }

  // Number of failures before the first success of a Bernoulli(p) sequence, 0 < p < 1,
  // given 1 / log1p(-p): lets a sparse mutation mask skip straight to the next mutated gene.
  // Single precision (u has 32 random bits): the distribution is exact to about 1e-7, and
  // logf costs a fraction of log on this hot path.
  std::uint32_t geometric(float inv_log1m_p) {
    const float u = static_cast<float>(((*this)() >> 32) + 1) * 0x1.0p-32f;  // (0, 1]
    const float g = std::floor(std::log(u) * inv_log1m_p);
    return g >= 4.0e9f ? 4'000'000'000U : static_cast<std::uint32_t>(g);
  }

  // A standard normal in single precision (polar method, both variates from one 64-bit draw
  // of 2 x 24 bits), for mutation; normal() is the double-precision one.
  float normal_float() {
    if (has_spare_float_) {
      has_spare_float_ = false;
      return spare_float_;
    }
    float u, v, s;
    do {
      const std::uint64_t bits = (*this)();
      u = static_cast<float>(bits >> 40) * 0x1.0p-23f - 1.0f;
      v = static_cast<float>((bits >> 16) & 0xFFFFFF) * 0x1.0p-23f - 1.0f;
      // Fused as GCC contracts it in the library's optimised files, written out so that a caller's
      // inline copy compiled without contraction (-O0, -ffp-contract=off) draws the same bits.
      s = fused(u, u, v * v);
    } while (s >= 1.0f || s == 0.0f);
    const float factor = std::sqrt(-2.0f * std::log(s) / s);
    spare_float_ = v * factor;
    has_spare_float_ = true;
    return u * factor;
  }

  struct State {
    std::array<std::uint64_t, 4> words{};
    bool has_spare = false;
    double spare = 0.0;
    bool has_spare_float = false;
    float spare_float = 0.0f;
    bool operator==(const State&) const = default;
  };
  State state() const { return {state_, has_spare_, spare_, has_spare_float_, spare_float_}; }
  void set_state(const State& s) {
    state_ = s.words;
    has_spare_ = s.has_spare;
    spare_ = s.spare;
    has_spare_float_ = s.has_spare_float;
    spare_float_ = s.spare_float;
  }

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::array<std::uint64_t, 4> state_{};
  bool has_spare_ = false;
  double spare_ = 0.0;
  bool has_spare_float_ = false;
  float spare_float_ = 0.0f;
};

// Keeps `count` items of `items` chosen uniformly without replacement, in draw order (a partial
// Fisher-Yates shuffle: exactly `count` calls of rng.below). count must be <= items.size().
template <class T>
void choose_without_replacement(std::vector<T>& items, std::size_t count, Rng& rng) {
  for (std::size_t i = 0; i < count; ++i) std::swap(items[i], items[i + rng.below(items.size() - i)]);
  items.resize(count);
}

// Purposes of derived streams, so that two components never share one by accident.
enum class StreamKey : std::uint64_t {
  kInitialPopulation = 1,
  kVariation = 2,
  kMetaFitness = 3,
  kMetaSampling = 4,
  kControl = 5,
  kTest = 6,
  kCentroids = 7,
  kAutoencoder = 8,
  kEmitterStart = 9,  // QD-Meta over CMA-MAE: each map's emitters' first means
};
inline std::uint64_t key(StreamKey k) { return static_cast<std::uint64_t>(k); }

}  // namespace qdmeta
