#include "qdmeta/emitters/evolution_strategy_emitter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

CmaEsParams cma_params(const EvolutionStrategyEmitterParams& p) {
  p.validate();
  CmaEsParams c;
  c.dimension = static_cast<int>(p.x0.size());
  c.population_size = p.batch_size;
  c.initial_sigma = p.sigma0;
  c.x0 = p.x0;
  c.bounds = p.bounds;
  c.lower_bound = p.lower_bound;
  c.upper_bound = p.upper_bound;
  c.eigen_gap = p.eigen_gap;
  c.rank_one = p.rank_one;
  return c;
}

std::variant<CmaEs, SepCmaEs> make_strategy(const EvolutionStrategyEmitterParams& p) {
  if (p.es == EvolutionStrategyKind::kSepCmaEs) return std::variant<CmaEs, SepCmaEs>(std::in_place_type<SepCmaEs>, cma_params(p));
  return std::variant<CmaEs, SepCmaEs>(std::in_place_type<CmaEs>, cma_params(p));
}

bool converged(double sigma, double d_max, double d_min, const std::vector<RankKey>& ranked_keys) {
  if ((d_max / d_min) * (d_max / d_min) > 1e14) return true;
  if (sigma * d_max < 1e-11) return true;
  if (ranked_keys.size() < 2) return false;
  const RankKey& best = ranked_keys.front();
  const RankKey& worst = ranked_keys.back();
  return std::hypot(best.stage - worst.stage, best.value - worst.value) < 1e-12;
}

}  // namespace

std::string to_string(EvolutionStrategyKind value) {
  return std::string(enum_to_string(kEvolutionStrategyKindNames, value));
}
EvolutionStrategyKind evolution_strategy_kind_from_string(std::string_view text) {
  return enum_from_string(kEvolutionStrategyKindNames, "evolution strategy", text);
}
std::string to_string(EmitterSelection value) { return std::string(enum_to_string(kEmitterSelectionNames, value)); }
EmitterSelection emitter_selection_from_string(std::string_view text) {
  return enum_from_string(kEmitterSelectionNames, "emitter selection rule", text);
}
std::string to_string(EmitterRestart value) { return std::string(enum_to_string(kEmitterRestartNames, value)); }
EmitterRestart emitter_restart_from_string(std::string_view text) {
  return enum_from_string(kEmitterRestartNames, "emitter restart rule", text);
}

void EvolutionStrategyEmitterParams::validate() const {
  if (x0.empty()) {
    throw InputError("EvolutionStrategyEmitterParams.x0 is empty: give the first mean, one value per gene");
  }
  require(kSigma0, sigma0);
  require(kEmitterBatchSize, batch_size);
  if (restart == EmitterRestart::kEveryN) require(kRestartEvery, restart_every);
  if (needs_direction(ranker) && measure_ranges.empty()) {
    throw InputError(fmt::format("EvolutionStrategyEmitterParams.measure_ranges is empty: the {} ranker needs the "
                                 "extent of each measure",
                                 to_string(ranker)));
  }
  for (std::size_t j = 0; j < measure_ranges.size(); ++j) {
    if (!std::isfinite(measure_ranges[j]) || measure_ranges[j] <= 0.0) {
      throw InputError(fmt::format("EvolutionStrategyEmitterParams.measure_ranges[{}] = {} is invalid: must be "
                                   "finite and > 0",
                                   j, measure_ranges[j]));
    }
  }
  if (es == EvolutionStrategyKind::kSepCmaEs && rank_one != CmaRankOne::kTutorial) {
    throw InputError(fmt::format("EvolutionStrategyEmitterParams.rank_one = {} is not available with es = sep-cma-es: "
                                 "only tutorial",
                                 to_string(rank_one)));
  }
  if (enum_to_string(kEvolutionStrategyKindNames, es) == "?") {
    throw InputError(fmt::format("EvolutionStrategyEmitterParams.es = {} is invalid: must be one of cma-es, sep-cma-es",
                                 static_cast<int>(es)));
  }
  if (enum_to_string(kEmitterRankerNames, ranker) == "?" || enum_to_string(kEmitterSelectionNames, selection) == "?" ||
      enum_to_string(kEmitterRestartNames, restart) == "?") {
    throw InputError("EvolutionStrategyEmitterParams: ranker, selection or restart is not one of its names");
  }
}

bool cma_converged(const CmaEsState& state, const std::vector<RankKey>& ranked_keys) {
  return converged(state.sigma, state.D.maxCoeff(), state.D.minCoeff(), ranked_keys);
}

bool cma_converged(const SepCmaEsState& state, const std::vector<RankKey>& ranked_keys) {
  return converged(state.sigma, std::sqrt(state.C.maxCoeff()), std::sqrt(state.C.minCoeff()), ranked_keys);
}

EvolutionStrategyEmitter::EvolutionStrategyEmitter(EvolutionStrategyEmitterParams params, ElitePicker pick_elite)
    : BatchEmitter(cma_params(params).population_size, static_cast<Index>(params.x0.size()), "EvolutionStrategyEmitter"),
      params_(std::move(params)),
      pick_elite_(std::move(pick_elite)),
      es_(make_strategy(params_)) {}

const CmaEs& EvolutionStrategyEmitter::optimiser() const {
  if (const auto* cma = std::get_if<CmaEs>(&es_)) return *cma;
  throw InputError("EvolutionStrategyEmitter::optimiser: this emitter runs es = sep-cma-es; use separable_optimiser()");
}

const SepCmaEs& EvolutionStrategyEmitter::separable_optimiser() const {
  if (const auto* sep = std::get_if<SepCmaEs>(&es_)) return *sep;
  throw InputError("EvolutionStrategyEmitter::separable_optimiser: this emitter runs es = cma-es; use optimiser()");
}

void EvolutionStrategyEmitter::restart(Rng& rng) {
  CmaEsParams p = std::visit([](const auto& es) { return es.params(); }, es_);
  std::vector<double> mean(static_cast<std::size_t>(solution_size()));
  if (pick_elite_ && pick_elite_(rng, mean)) {
    // An elite stored in single precision may round just past a bound; CMA-ES wants its mean inside.
    if (p.bounds != CmaBoundsHandling::kNone) {
      for (double& m : mean) m = std::clamp(m, p.lower_bound, p.upper_bound);
    }
    p.x0 = std::move(mean);
  }
  std::visit([&p](auto& es) { es.set_state(es.initial_state(p)); }, es_);
  draw_direction(rng);
  restarts_ += 1;
  restart_pending_ = false;
}

void EvolutionStrategyEmitter::draw_direction(Rng& rng) {
  if (!needs_direction(params_.ranker)) return;
  direction_.resize(params_.measure_ranges.size());
  for (std::size_t j = 0; j < direction_.size(); ++j) direction_[j] = rng.normal() * params_.measure_ranges[j];
}

const RowMatrix& EvolutionStrategyEmitter::ask(Rng& rng) {
  check_ask();
  if (restart_pending_) {
    restart(rng);
  } else if (direction_.empty()) {
    draw_direction(rng);
  }
  const Eigen::MatrixXd& samples = std::visit([&rng](auto& es) -> const Eigen::MatrixXd& { return es.ask(rng); }, es_);
  for (Index r = 0; r < batch_.rows(); ++r) {
    for (Index j = 0; j < batch_.cols(); ++j) batch_(r, j) = static_cast<Real>(samples(j, r));
  }
  awaiting_tell_ = true;
  return batch_;
}

void EvolutionStrategyEmitter::tell(const EmitterResults& results) {
  check_tell(results);
  const std::vector<RankKey> keys = rank_keys(params_.ranker, results, direction_);  // may refuse the measures
  const std::vector<int> order = rank_order(keys);
  awaiting_tell_ = false;
  tells_ += 1;
  const auto added = static_cast<int>(std::count_if(results.outcomes.begin(), results.outcomes.end(),
                                                     [](const ThresholdOutcome& o) { return o.status != AddStatus::kNotAdded; }));
  last_parents_ = params_.selection == EmitterSelection::kFilter ? added : std::max(1, params_.batch_size / 2);
  std::visit([&](auto& es) { es.tell_ranked(order, last_parents_); }, es_);

  std::vector<RankKey> ranked(keys.size());
  for (std::size_t k = 0; k < order.size(); ++k) ranked[k] = keys[static_cast<std::size_t>(order[k])];
  bool fire = std::visit([&ranked](const auto& es) { return cma_converged(es.state(), ranked); }, es_);
  switch (params_.restart) {
    case EmitterRestart::kNoImprovement: fire = fire || added == 0; break;
    case EmitterRestart::kBasic: break;
    case EmitterRestart::kEveryN: fire = fire || tells_ % params_.restart_every == 0; break;
  }
  restart_pending_ = fire;
}

void EvolutionStrategyEmitter::save(BinaryWriter& out) const {
  out.tag("evolution strategy emitter");
  std::visit([&out](const auto& es) { es.save(out); }, es_);
  save_batch(out);
  out.value(tells_);
  out.value(restarts_);
  out.boolean(restart_pending_);
  out.value(last_parents_);
  out.values(direction_);
}

void EvolutionStrategyEmitter::load(BinaryReader& in) {
  in.expect_tag("evolution strategy emitter");
  std::visit([&in](auto& es) { es.load(in); }, es_);
  load_batch(in);
  tells_ = in.value<std::int64_t>("emitter tells");
  restarts_ = in.value<std::int64_t>("emitter restarts");
  restart_pending_ = in.boolean("emitter restart flag");
  last_parents_ = in.value<int>("emitter parents");
  direction_ = in.values<double>("emitter direction");
  if (!direction_.empty() && direction_.size() != params_.measure_ranges.size()) {
    in.fail(fmt::format("the emitter direction has {} values, expected {}", direction_.size(),
                        params_.measure_ranges.size()));
  }
}

}  // namespace qdmeta
