#pragma once
// A U-Tree-style regression tree that discretises a continuous observation into states
// (Uther & Veloso 1998, as used by Karafotias et al. 2014; docs/specification.md, SARSA(lambda) control). Each leaf is a
// state: it holds the Q-values and eligibility traces of its actions and the transitions seen
// from it (the observation and the value r + V(s')). A leaf with enough transitions may split
// on the attribute threshold whose two sides differ most by a two-sample Kolmogorov-Smirnov
// test; the children inherit the leaf's Q-values and traces.
#include <cstdint>
#include <optional>
#include <vector>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {

struct StateTreeParams {
  // The config parameters read into this struct and checked by validate() (core/params.hpp) (SARSA's actions too).
  static constexpr IntParam kActions{"control", "actions", 1, 1'000,
      "equal intervals of [min, max]; the G used is drawn uniformly in the chosen interval and rounded"};
  static constexpr IntParam kSplitMinTransitions{"control", "split_min_transitions", 2, 1'000'000'000,
      "a state (leaf) tries to split only above this many stored transitions"};
  static constexpr RealParam kSplitProbability{"control", "split_probability", 0.0, 1.0, Open::kNone,
      "chance of trying, per transition added to such a leaf"};
  static constexpr RealParam kSplitMinFraction{"control", "split_min_fraction", 0.0, 0.5, Open::kBoth,
      "each side of a split keeps at least this fraction of the transitions"};
  static constexpr IntParam kMaxCandidates{"control", "max_candidates", 1, 1'000'000,
      "candidate thresholds per attribute; positions are strided beyond twice this many"};
  static constexpr RealParam kMinValueGap{"control", "min_value_gap", 0.0, kNoUpper, Open::kNone,
      "no threshold between attribute values closer than this"};
  static constexpr RealParam kKsAlpha{"control", "ks_alpha", 0.0, 1.0, Open::kBoth,
      "significance level of the two-sample Kolmogorov-Smirnov split test"};
  int attributes = 6;               // observation size
  int actions = 5;                  // Q-values per state
  std::size_t split_min_transitions = 60;  // a leaf needs more than this to try a split
  double split_probability = 0.1;   // chance of trying, per transition added to such a leaf
  double split_min_fraction = 0.2;  // each side keeps at least this fraction of the transitions
  std::size_t max_candidates = 100; // candidate positions per attribute before striding
  double min_value_gap = 0.001;     // neighbouring attribute values closer than this: no cut
  double ks_alpha = 0.05;           // significance level of the KS test
  void validate() const;
};

struct StateTransition {
  std::vector<double> observation;
  double value = 0.0;  // r + V(s')
};

// A split the tree made: which leaf, on what, and how strongly the sides differed.
struct StateSplit {
  int leaf = -1;
  int attribute = -1;
  double threshold = 0.0;
  double statistic = 0.0;
  double critical = 0.0;
  int left = -1, right = -1;  // the new leaves
};

class StateTree {
 public:
  struct Node {
    int attribute = -1;  // -1 for a leaf
    double threshold = 0.0;
    int left = -1, right = -1;
    std::vector<double> q;      // leaves only
    std::vector<double> trace;  // leaves only
    std::vector<StateTransition> transitions;  // leaves only
    bool leaf() const { return attribute < 0; }
  };

  explicit StateTree(StateTreeParams params);

  // The leaf (state) an observation falls in: left when obs[attribute] < threshold.
  int leaf_of(const std::vector<double>& observation) const;
  std::size_t leaf_count() const { return leaves_; }
  const Node& node(int id) const { return nodes_.at(static_cast<std::size_t>(id)); }
  Node& node(int id) { return nodes_.at(static_cast<std::size_t>(id)); }
  const std::vector<Node>& nodes() const { return nodes_; }
  const StateTreeParams& params() const { return params_; }

  // Stores a transition in `leaf`; if the leaf then holds more than split_min_transitions,
  // tries (with probability split_probability, drawn from rng) to split it.
  std::optional<StateSplit> add_transition(int leaf, StateTransition transition, Rng& rng);
  // Tries to split `leaf` now, whatever its size and the split probability.
  std::optional<StateSplit> try_split(int leaf);

  // Checkpoints: every node with its Q-values, traces and transitions. load() requires the
  // same attribute and action counts.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

 private:
  StateTreeParams params_;
  std::vector<Node> nodes_;
  std::size_t leaves_ = 1;
};

}  // namespace qdmeta
