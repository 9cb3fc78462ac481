#include "qdmeta/control/sarsa_control.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void SarsaParams::validate() const {
  require(StateTreeParams::kActions, actions);
  require(kMinGenerations, min_generations);
  require(kMaxGenerations.from(min_generations), max_generations);
  require(kEpsilon, epsilon);
  require(kGamma, gamma);
  require(kAlpha, alpha);
  require(kAlphaZeroReward, alpha_zero_reward);
  require(kTraceDecay, trace_decay);
  require(kTraceMin, trace_min);
  require(kRewardScale, reward_scale);
  require(kRewardMax, reward_max);
  tree.validate();
}

namespace {
SarsaParams complete(SarsaParams p) {
  p.tree.attributes = kObservationSize;
  p.tree.actions = p.actions;
  p.validate();
  return p;
}
double value_of(const std::vector<double>& q) { return std::max(0.0, *std::max_element(q.begin(), q.end())); }
}  // namespace

SarsaControl::SarsaControl(SarsaParams params) : params_(complete(params)), tree_(params_.tree) {}

std::pair<double, double> SarsaControl::interval(int action) const {
  const double width = static_cast<double>(params_.max_generations - params_.min_generations) / params_.actions;
  const double lo = params_.min_generations + width * action;
  return {lo, lo + width};
}

std::pair<int, int> SarsaControl::action_range(int action) const {
  const auto [lo, hi] = interval(action);
  const auto clamp = [&](long g) {
    return static_cast<int>(std::clamp<long>(g, params_.min_generations, params_.max_generations));
  };
  // The draw is uniform in [lo, hi) and rounded, so hi itself is reached only when it is
  // above a rounding midpoint.
  return {clamp(std::lround(lo)), clamp(std::lround(std::nextafter(hi, lo)))};
}

double SarsaControl::sample_diversity(const Eigen::MatrixXd& samples) {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < samples.cols(); ++i)
    for (Eigen::Index j = i + 1; j < samples.cols(); ++j) sum += (samples.col(i) - samples.col(j)).squaredNorm();
  return sum;
}

double SarsaControl::reward(double best, double previous_best, std::int64_t evaluations) const {
  if (evaluations < 1) throw Error("sarsa control: a meta-generation reported no evaluations");
  double r;
  if (previous_best == 0.0) r = best > 0.0 ? params_.reward_max : 0.0;  // relative change undefined
  else r = (best - previous_best) / std::abs(previous_best) / static_cast<double>(evaluations) * params_.reward_scale;
  return std::clamp(r, 0.0, params_.reward_max);
}

int SarsaControl::choose_action(int leaf, Rng& rng) const {
  if (rng.uniform() < params_.epsilon) return static_cast<int>(rng.below(static_cast<std::uint64_t>(params_.actions)));
  // Greedy, ties broken at random: at the start every Q is 0 and a fixed tie-break would
  // always pick the first interval.
  const std::vector<double>& q = tree_.node(leaf).q;
  const double top = *std::max_element(q.begin(), q.end());
  std::vector<int> best;
  for (int a = 0; a < params_.actions; ++a)
    if (q[static_cast<std::size_t>(a)] == top) best.push_back(a);
  return best.size() == 1 ? best[0] : best[rng.below(best.size())];
}

int SarsaControl::draw_generations(int action, Rng& rng) const {
  const auto [lo, hi] = interval(action);
  const long g = std::lround(rng.uniform(lo, hi));
  return static_cast<int>(std::clamp<long>(g, params_.min_generations, params_.max_generations));
}

void SarsaControl::learn(int next_leaf, int next_action, Rng& rng) {
  const auto a = static_cast<std::size_t>(action_);
  const auto a_next = static_cast<std::size_t>(next_action);
  const double alpha = reward_ == 0.0 ? params_.alpha_zero_reward : params_.alpha;
  const double delta = reward_ + params_.gamma * tree_.node(next_leaf).q[a_next] - tree_.node(leaf_).q[a];
  // Replacing traces: every other pair decays by gamma x lambda (and is dropped when tiny),
  // the pair just taken is set to 1; then every eligible pair moves toward the target.
  const double decay = params_.gamma * params_.trace_decay;
  for (std::size_t id = 0; id < tree_.nodes().size(); ++id) {
    StateTree::Node& n = tree_.node(static_cast<int>(id));
    for (double& e : n.trace) e = e * decay < params_.trace_min ? 0.0 : e * decay;
  }
  tree_.node(leaf_).trace[a] = 1.0;
  for (std::size_t id = 0; id < tree_.nodes().size(); ++id) {
    StateTree::Node& n = tree_.node(static_cast<int>(id));
    for (std::size_t k = 0; k < n.trace.size(); ++k) n.q[k] += alpha * delta * n.trace[k];
  }
  // The first meta-generation had no observation, so it leaves no transition for splitting.
  if (observation_) {
    const double value = reward_ + value_of(tree_.node(next_leaf).q);
    tree_.add_transition(leaf_, {*observation_, value}, rng);
  }
}

int SarsaControl::choose_generations(const Eigen::MatrixXd& samples, Rng& rng) {
  if (!has_statistics_) {
    // First meta-generation: no statistics yet. Act from the initial state, learn nothing.
    if (action_ >= 0) throw Error("sarsa control: choose_generations called twice without observe");
    leaf_ = tree_.leaf_of(std::vector<double>(kObservationSize, 0.0));
    observation_.reset();
    action_ = choose_action(leaf_, rng);
    return draw_generations(action_, rng);
  }
  std::vector<double> observation(kObservationSize);
  observation[kObsBest] = best_;
  observation[kObsMean] = mean_;
  observation[kObsSd] = sd_;
  observation[kObsDiversity] = sample_diversity(samples);
  observation[kObsStagnation] = stagnation_;
  observation[kObsReward] = reward_;
  const int next_leaf = tree_.leaf_of(observation);
  const int next_action = choose_action(next_leaf, rng);
  learn(next_leaf, next_action, rng);
  leaf_ = tree_.leaf_of(observation);  // the leaf may have split during learning
  observation_ = std::move(observation);
  action_ = next_action;
  return draw_generations(action_, rng);
}

void SarsaControl::observe(std::span<const double> meta_fitness, std::int64_t evaluations) {
  if (meta_fitness.empty()) throw Error("sarsa control: no meta-fitness to observe");
  if (action_ < 0) throw Error("sarsa control: observe called before choose_generations");
  const double best = *std::max_element(meta_fitness.begin(), meta_fitness.end());
  const double mean = std::accumulate(meta_fitness.begin(), meta_fitness.end(), 0.0) / static_cast<double>(meta_fitness.size());
  double sq = 0.0;
  for (double f : meta_fitness) sq += (f - mean) * (f - mean);
  if (has_statistics_) {
    reward_ = reward(best, best_, evaluations);
    stagnation_ = best > best_ ? 0 : stagnation_ + 1;
  } else {
    reward_ = 0.0;  // no previous best (docs/fidelity.md: not the authors' uninitialised read)
    stagnation_ = 0;
  }
  best_ = best;
  mean_ = mean;
  sd_ = std::sqrt(sq / static_cast<double>(meta_fitness.size()));
  has_statistics_ = true;
}


void SarsaControl::save(BinaryWriter& out) const {
  out.tag("sarsa_control");
  tree_.save(out);
  out.value<std::int32_t>(leaf_);
  out.boolean(observation_.has_value());
  if (observation_) out.values(*observation_);
  out.value<std::int32_t>(action_);
  out.boolean(has_statistics_);
  out.value(best_);
  out.value(mean_);
  out.value(sd_);
  out.value(reward_);
  out.value<std::int32_t>(stagnation_);
}

void SarsaControl::load(BinaryReader& in) {
  in.expect_tag("sarsa_control");
  tree_.load(in);
  leaf_ = in.value<std::int32_t>("controller state");
  if (leaf_ < 0 || static_cast<std::size_t>(leaf_) >= tree_.nodes().size() || !tree_.node(leaf_).leaf())
    in.fail("controller state is not a leaf of its tree");
  observation_.reset();
  if (in.boolean("controller observation flag")) {
    observation_ = in.values<double>("controller observation");
    if (observation_->size() != kObservationSize) in.fail("controller observation of the wrong size");
  }
  action_ = in.value<std::int32_t>("controller action");
  if (action_ < -1 || action_ >= params_.actions) in.fail("controller action out of range");
  has_statistics_ = in.boolean("controller statistics flag");
  best_ = in.value<double>("controller best");
  mean_ = in.value<double>("controller mean");
  sd_ = in.value<double>("controller SD");
  reward_ = in.value<double>("controller reward");
  stagnation_ = in.value<std::int32_t>("controller stagnation");
}

}  // namespace qdmeta
