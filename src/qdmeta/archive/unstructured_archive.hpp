#pragma once
// AURORA's unstructured archive (docs/specification.md, AURORA; the distance-based container of Cully &
// Demiris's sferes2 `qd` module): elites live at free points of a descriptor space; a
// candidate at distance d1 from its nearest member and d2 from its second nearest, against a
// distance threshold l, is
//   - added              when the archive is empty or d1 > l;
//   - rejected           when d2 < (1 - eps) l (or the archive holds only the nearest member);
//   - put in the nearest member's place when it eps-dominates that member on (fitness, novelty),
//     novelty = mean distance to the k nearest members (for the candidate: other than the
//     nearest one, which it may replace; for the member: other than itself);
//   - rejected otherwise.
// The threshold is the caller's (AURORA adapts it); each call passes the one in force.
//
// Members occupy slots 0..size-1; a replacement keeps the slot. Neighbour queries are exact
// (archive/point_grid.hpp: ties broken by the lower slot, so results never depend on the
// index; bench/README.md compares it with a brute-force scan and a k-d tree). The neighbourhoods
// of a candidate and of its nearest member are gathered in one pass over rings of grid cells,
// which stops as soon as what it has seen decides the rule.
#include <cstdint>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/elite_batch.hpp"  // AddStatus
#include "qdmeta/archive/point_grid.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct UnstructuredArchiveParams {
  // AURORA's config parameters that the archive checks (core/params.hpp).
  static constexpr IntParam kTargetSize{"aurora", "target_size", 1, 100'000'000,
      "container size control's target (paper: 10,000 Rastrigin, 4,096 RHex); `coverage` = min(1, size / "
      "target) and `norm_qd_score` = qd_score / target"};
  static constexpr RealParam kEps{"aurora", "eps", 0.0, 0.999, Open::kNone,
      "the insertion rule's eps: a candidate within l of its nearest member is rejected when its second "
      "nearest is closer than (1 - eps) l, and replaces the nearest only if it eps-dominates it on "
      "(fitness, novelty); rebuilds re-add with l (1 - eps)"};
  static constexpr IntParam kNoveltyNeighbours{"aurora", "novelty_neighbours", 1, 1'000'000,
      "k: novelty = mean distance to the k nearest members"};
  Index measure_size = 2;       // dimensions of a measure (AURORA: the latent size), >= 1
  Index solution_size = 0;      // genes per solution, >= 1
  Index base_feature_size = 0;  // base features kept per elite (0: none)
  Index target_size = 10'000;   // the size AURORA steers toward; coverage = min(1, size / target)
  double eps = 0.1;             // eps of the second-neighbour rule and of eps-dominance, in [0, 1)
  int novelty_neighbours = 15;  // k of the novelty score, >= 1
  double qd_offset = 0.0;       // QD-score counts objective - qd_offset
  void validate() const;
};

// True when (fitness, novelty) of a candidate eps-dominates those of a member, as in sferes2's
// archive: both at least (1 - sign(member's) eps) times the member's, and the candidate's gain
// on one outweighs its loss on the other, each weighed by the member's other score.
bool eps_dominates(double candidate_fitness, double candidate_novelty, double member_fitness, double member_novelty,
                   double eps);
// Its first condition, on fitness alone: false makes eps_dominates false whatever the novelties.
bool eps_fitness_allows(double candidate_fitness, double member_fitness, double eps);

class UnstructuredArchive {
 public:
  explicit UnstructuredArchive(UnstructuredArchiveParams params);

  const UnstructuredArchiveParams& params() const { return params_; }
  Index size() const { return static_cast<Index>(objectives_.size()); }
  bool empty() const { return objectives_.empty(); }

  // Applies the insertion rule above with threshold l (> 0). kImproved means a replacement.
  // `slot`, when given, receives the slot written (kNew, kImproved) or -1.
  AddStatus add(const Real* solution, Real objective, const Real* descriptor, const Real* base_features,
                double threshold, Index* slot = nullptr);
  // Empties the archive and adds `count` rows (row-major: solutions, descriptors and base
  // features, the latter null when base_feature_size = 0) in order with threshold l: the archive
  // that clear() and one add() per row would leave, and the same error at the first
  // non-finite descriptor. A row farther than l from every earlier row enters without a query
  // (no earlier row, hence no member, is near it); those rows are found on oneTBB's threads.
  // `rows`, when given, receives the row each slot holds after the refill.
  void refill(Index count, const Real* solutions, const Real* objectives, const Real* descriptors,
              const Real* base_features, double threshold, std::vector<Index>* rows = nullptr);
  void clear();
  // Checkpoints: every member in slot order; load() re-adds them in that order (slots and the
  // neighbour grid as before; queries do not depend on the order inside a grid cell).
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

  Real objective(Index slot) const { return objectives_[static_cast<std::size_t>(slot)]; }
  const Real* solution(Index slot) const { return solutions_.data() + slot * params_.solution_size; }
  const Real* base_features(Index slot) const { return base_.data() + slot * params_.base_feature_size; }
  Real descriptor(Index slot, Index dimension) const {
    return coordinates_[static_cast<std::size_t>(dimension)][static_cast<std::size_t>(slot)];
  }
  // A member drawn uniformly. The archive must not be empty.
  Index sample(Rng& rng) const { return static_cast<Index>(rng.below(objectives_.size())); }

  // Novelty of a member: mean distance to its k nearest other members (0 when alone).
  double member_novelty(Index slot) const;

  using Neighbour = qdmeta::Neighbour;
  // The `count` members nearest to `point` other than slot `excluded` (-1: none), nearest first.
  std::vector<Neighbour> nearest(const Real* point, Index count, Index excluded = -1) const;

  ArchiveStats stats() const;

 private:
  // add() once the descriptor is known to be finite and the archive not empty.
  AddStatus add_near(const Real* solution, Real objective, const Real* descriptor, const Real* base_features,
                     double threshold, Index* slot);
  void append(const Real* solution, Real objective, const Real* descriptor, const Real* base_features);
  void overwrite(Index slot, const Real* solution, Real objective, const Real* descriptor, const Real* base_features);
  void check_finite(const Real* descriptor) const;
  // add()'s novelty of the nearest member `slot` (into around_) from the points gathered around
  // the candidate; false when those do not yet reach far enough to make it exact.
  bool member_neighbours(Index slot, double nearest, double farthest, double reach);

  UnstructuredArchiveParams params_;
  std::vector<Real> objectives_;
  std::vector<Real> solutions_;                  // size x solution_size
  std::vector<Real> base_;                       // size x base_feature_size
  std::vector<std::vector<Real>> coordinates_;   // measure_size arrays of size entries, by slot
  PointGrid grid_;                               // the members' descriptors by slot
  // add()'s scratch: the cells seen around the candidate, its nearest and its nearest's nearest.
  std::vector<PointGrid::Span> spans_;
  NearestKeys near_, around_;
  std::vector<Real> member_;  // the nearest member's descriptor
  RowsApart rows_apart_;      // refill()'s
};

}  // namespace qdmeta
