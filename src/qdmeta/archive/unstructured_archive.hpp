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
// and use a uniform grid over the first two descriptor coordinates (128 x 128 cells over
// [-4, 4]^2, where AURORA's z-scored codes live; members beyond share the edge cells, which
// keeps queries exact, only slower): cells are visited in square rings around the query's cell
// until the ring's distance alone exceeds the k-th best distance found. Ties are broken by the
// lower slot, so results never depend on the visiting order (bench/README.md compares this
// with a brute-force scan and a k-d tree).
#include <cstdint>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/elite_batch.hpp"  // AddStatus
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct UnstructuredArchiveParams {
  Index descriptor_size = 2;    // dimensions of the descriptor (AURORA: the latent size), >= 1
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

class UnstructuredArchive {
 public:
  explicit UnstructuredArchive(UnstructuredArchiveParams params);

  const UnstructuredArchiveParams& params() const { return params_; }
  Index size() const { return static_cast<Index>(objectives_.size()); }
  bool empty() const { return objectives_.empty(); }

  // Applies the insertion rule above with threshold l (> 0). kImproved means a replacement.
  AddStatus add(const Real* solution, Real objective, const Real* descriptor, const Real* base_features,
                double threshold);
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

  struct Neighbour {
    Real squared_distance;
    Index slot;
    bool operator<(const Neighbour& o) const {
      return squared_distance < o.squared_distance || (squared_distance == o.squared_distance && slot < o.slot);
    }
  };
  // The `count` members nearest to `point` other than slot `excluded` (-1: none), nearest first.
  std::vector<Neighbour> nearest(const Real* point, Index count, Index excluded = -1) const;

  ArchiveStats stats() const;

 private:
  void append(const Real* solution, Real objective, const Real* descriptor, const Real* base_features);
  void overwrite(Index slot, const Real* solution, Real objective, const Real* descriptor, const Real* base_features);

  UnstructuredArchiveParams params_;
  std::vector<Real> objectives_;
  std::vector<Real> solutions_;                  // size x solution_size
  std::vector<Real> base_;                       // size x base_feature_size
  std::vector<std::vector<Real>> coordinates_;   // descriptor_size arrays of size entries, by slot
  // The grid index: the slots in each cell, and each slot's cell.
  std::vector<std::vector<Index>> cells_;
  std::vector<std::int32_t> cell_of_slot_;
  Index grid_dims_ = 1;  // 1 or 2: the coordinates the grid spans
  std::int32_t cell_of(const Real* point, std::int32_t* column_row = nullptr) const;
  void index_insert(Index slot);
  void index_erase(Index slot);
};

}  // namespace qdmeta
