#pragma once
// The emitter choice of pyribs's BanditScheduler (Cully 2021, "Multi-emitter MAP-Elites"):
// num_active emitters of a pool are asked at a time; when some must be chosen again (reselect
// "terminated": those whose run ended, and every emitter without runs; "all": every active
// one), they are dropped and the free places go to the emitters of highest UCB1 value,
//   ucb1_i = s_i / n_i + zeta sqrt(ln(sum_k s_k) / n_i),
// with n_i the rows emitter i was asked for and s_i those the archive took (+inf for an emitter
// never asked). The order is pyribs's: its values sorted ascending by numpy's insertion sort
// (which it uses on up to 16 values), taken from the top, so ties go to the higher pool index,
// and the NaN of ln 0 (no success yet anywhere), which compares false, keeps its place. On a
// pool over 16 the ties (and NaN) may fall otherwise in pyribs; the values rank the same.
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

enum class BanditReselect { kTerminated, kAll };
// "terminated" or "all"; InputError naming the value otherwise.
BanditReselect bandit_reselect_from_string(std::string_view text);

struct BanditParams {
  int num_active = 1;                                   // emitters asked at a time, in [1, pool]
  BanditReselect reselect = BanditReselect::kTerminated;
  double zeta = 0.05;                                   // UCB1's exploration weight (finite, >= 0)
  // Throws InputError naming the field, its value and the rule it breaks.
  void validate(std::size_t pool) const;
  friend bool operator==(const BanditParams&, const BanditParams&) = default;
};

class EmitterBandit {
 public:
  EmitterBandit(std::size_t pool, BanditParams params);

  const BanditParams& params() const { return params_; }
  std::size_t pool() const { return active_.size(); }
  // One flag per pool emitter: those the last choose() activated (none before the first).
  const std::vector<std::uint8_t>& active() const { return active_; }
  double successes(std::size_t i) const { return success_[i]; }
  double selections(std::size_t i) const { return selection_[i]; }
  // UCB1's value of emitter i (+inf when never asked; NaN while no emitter has a success).
  double ucb1(std::size_t i) const;

  // The emitters to ask next, given each one's ended_runs() (emitter.hpp).
  const std::vector<std::uint8_t>& choose(std::span<const std::int64_t> ended_runs);
  // Emitter i was asked for `rows` rows, of which the archive took `successes`.
  void record(std::size_t i, Index rows, Index successes);

  void save(BinaryWriter& out) const;
  // Requires a bandit built with the same pool and params; InputError otherwise.
  void load(BinaryReader& in);

 private:
  void fill_by_ucb1();

  BanditParams params_;
  std::vector<std::uint8_t> active_;
  std::vector<double> success_, selection_;
  std::vector<std::int64_t> runs_seen_;
};

}  // namespace qdmeta
