#pragma once
// The proximity archive of novelty search, with pyribs's ProximityArchive's rules: a candidate's
// novelty is its mean Euclidean distance to its k nearest elites (fewer while the archive holds
// fewer; the novelty threshold itself while it is empty), judged against the archive as it was
// before the batch; a candidate at least `novelty_threshold` novel is added. With local
// competition, one that is not novel enough replaces its nearest elite when its objective is
// higher (of several candidates for one elite, the best, the first on ties). With threshold
// decay, `threshold_decay_itrs` adds in a row that add nothing novel multiply the threshold by
// `threshold_decay_rate`, down to `threshold_decay_min`.
// Elites are kept in double, in the order they came (a replacement takes its elite's place).
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/kd_tree.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct ProximityArchiveParams {
  Index solution_size = 1;
  Index measure_size = 2;
  Index k_neighbors = 15;          // >= 1
  double novelty_threshold = 0.1;  // finite, >= 0
  bool local_competition = false;
  std::optional<double> threshold_decay_rate;  // in (0, 1] when given
  Index threshold_decay_itrs = 1;              // >= 1
  double threshold_decay_min = 0.0;            // >= 0
  double qd_offset = 0.0;                      // QD-score counts objective - qd_offset
  // Throws InputError naming the first setting out of its range.
  void validate() const;
};

// What add() did with each candidate, pyribs's names and codes: status 0 not added, 1 replaced
// its nearest elite (local competition), 2 added as novel; novelty as judged; with local
// competition, how many of its k nearest had a lower objective, and value: the objective for a
// novel one, else its objective minus its nearest elite's.
struct ProximityAddResult {
  std::vector<std::uint8_t> status;
  std::vector<double> novelty;
  std::vector<std::int32_t> local_competition;  // empty without local competition
  std::vector<double> value;                    // empty without local competition
};

class ProximityArchive {
 public:
  explicit ProximityArchive(const ProximityArchiveParams& params);

  // Adds a batch: solutions (n x solution_size), objectives (n) and measures (n x measure_size),
  // row-major. Refuses, naming the argument, a shape that does not fit or a non-finite value.
  ProximityAddResult add(std::span<const double> solutions, std::span<const double> objectives,
                         std::span<const double> measures);

  // The novelty of each row of `measures` (n x measure_size) against the archive as it is.
  std::vector<double> novelty(std::span<const double> measures) const;
  // The index of the nearest elite to each row of `measures` (ties as the k-d tree meets them); the archive
  // must hold at least one elite.
  std::vector<Index> index_of(std::span<const double> measures) const;

  Index size() const { return static_cast<Index>(objectives_.size()); }
  const ProximityArchiveParams& params() const { return params_; }
  double novelty_threshold() const { return threshold_; }
  std::span<const double> solutions() const { return solutions_; }
  std::span<const double> objectives() const { return objectives_; }
  std::span<const double> measures() const { return measures_; }
  // pyribs's statistics; every elite is its own cell, so coverage is 1 once one is there.
  ArchiveStats stats() const;

  // Checkpoints for bit-exact continuation: the elites, the threshold and its decay count.
  // load() requires an archive of the same solution and measure sizes (InputError otherwise)
  // and refuses a non-finite value.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

 private:
  // The min(k, size()) nearest elites to `point`, nearest first, with their distances.
  std::size_t nearest(const double* point, std::size_t k, std::vector<std::size_t>& elites,
                      std::vector<double>& distances) const;
  void replace(Index elite, const double* solution, double objective, const double* measures);
  void append(const double* solution, double objective, const double* measures);
  void update_threshold(Index novel_added);

  ProximityArchiveParams params_;
  double threshold_;
  Index adds_without_novel_ = 0;
  std::vector<double> solutions_;
  std::vector<double> objectives_;
  std::vector<double> measures_;
  // Over measures_ as of the last change; shared by copies, rebuilt (never changed) on a change.
  std::shared_ptr<const KdTree> tree_;
};

}  // namespace qdmeta
