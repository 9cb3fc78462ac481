#pragma once
// The rankers of CMA-ME's emitters (Fontaine et al. 2020; pyribs's ribs/emitters/rankers.py):
// how an emitter orders its told batch before CMA-ES takes the best as parents. Ties keep ask()
// order, so a ranking is a function of the results alone.
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/core/params.hpp"
#include "qdmeta/emitters/emitter.hpp"

namespace qdmeta {

enum class EmitterRanker {
  kImprovement,          // by improvement value f - t_e (CMA-MAE's ranker)
  kTwoStageImprovement,  // new cells first, then improved cells, then the rest; each by improvement (CMA-ME's)
  kObjective,            // by objective (an optimising emitter)
  kTwoStageObjective,    // added rows (new or improved) first, then the rest; each by objective
  kRandomDirection,      // by the projection of the measures on a random direction (the emitter draws it)
  kTwoStageRandomDirection,  // new, improved, then the rest; each by that projection
};
inline constexpr EnumNames<EmitterRanker, 6> kEmitterRankerNames{
    {{EmitterRanker::kImprovement, "improvement"},
     {EmitterRanker::kTwoStageImprovement, "two-stage-improvement"},
     {EmitterRanker::kObjective, "objective"},
     {EmitterRanker::kTwoStageObjective, "two-stage-objective"},
     {EmitterRanker::kRandomDirection, "random-direction"},
     {EmitterRanker::kTwoStageRandomDirection, "two-stage-random-direction"}}};
// True for the rankers that need a direction in measure space.
inline bool needs_direction(EmitterRanker ranker) {
  return ranker == EmitterRanker::kRandomDirection || ranker == EmitterRanker::kTwoStageRandomDirection;
}
std::string to_string(EmitterRanker value);
// Accepts the names above; anything else throws InputError listing them.
EmitterRanker emitter_ranker_from_string(std::string_view text);

// One row's rank key: `stage` first (higher first), then `value` (higher first).
struct RankKey {
  int stage = 0;
  double value = 0.0;
};

// The rows' keys under `ranker`; `direction` (one value per measure) is read by the
// random-direction rankers only, and the projection sums over the measures in order.
std::vector<RankKey> rank_keys(EmitterRanker ranker, const EmitterResults& results,
                               std::span<const double> direction = {});
// The rows' indices, best first (a stable order: ties keep ask() order).
std::vector<int> rank_order(const std::vector<RankKey>& keys);

}  // namespace qdmeta
