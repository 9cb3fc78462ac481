#include "qdmeta/control/state_tree.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "qdmeta/control/ks_test.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void StateTreeParams::validate() const {
  require_range("control.attributes", attributes, 1, 1000);
  require(kActions, actions);
  require(kSplitMinTransitions, split_min_transitions);
  require(kSplitProbability, split_probability);
  require(kSplitMinFraction, split_min_fraction);
  require(kMaxCandidates, max_candidates);
  require(kMinValueGap, min_value_gap);
  require(kKsAlpha, ks_alpha);
}

StateTree::StateTree(StateTreeParams params) : params_((params.validate(), params)) {
  Node root;
  root.q.assign(static_cast<std::size_t>(params_.actions), 0.0);
  root.trace.assign(static_cast<std::size_t>(params_.actions), 0.0);
  nodes_.push_back(std::move(root));
}

int StateTree::leaf_of(const std::vector<double>& observation) const {
  if (observation.size() != static_cast<std::size_t>(params_.attributes))
    throw Error(fmt::format("state tree: observation has {} attributes, expected {}", observation.size(),
                            params_.attributes));
  int id = 0;
  while (!nodes_[static_cast<std::size_t>(id)].leaf()) {
    const Node& n = nodes_[static_cast<std::size_t>(id)];
    id = observation[static_cast<std::size_t>(n.attribute)] < n.threshold ? n.left : n.right;
  }
  return id;
}

std::optional<StateSplit> StateTree::add_transition(int leaf, StateTransition transition, Rng& rng) {
  Node& n = node(leaf);
  if (!n.leaf()) throw Error(fmt::format("state tree: node {} is not a leaf", leaf));
  if (transition.observation.size() != static_cast<std::size_t>(params_.attributes))
    throw Error("state tree: transition observation has the wrong size");
  n.transitions.push_back(std::move(transition));
  if (n.transitions.size() <= params_.split_min_transitions) return std::nullopt;
  if (rng.uniform() >= params_.split_probability) return std::nullopt;
  return try_split(leaf);
}

std::optional<StateSplit> StateTree::try_split(int leaf) {
  const Node& n = node(leaf);
  const std::size_t count = n.transitions.size();
  const auto min_side = std::max<std::size_t>(1, static_cast<std::size_t>(params_.split_min_fraction * static_cast<double>(count)));
  if (count < 2 * min_side) return std::nullopt;
  const std::size_t span = count - 2 * min_side;
  const std::size_t stride =
      span > 2 * params_.max_candidates
          ? static_cast<std::size_t>(std::lround(static_cast<double>(span) / static_cast<double>(params_.max_candidates)))
          : 1;

  StateSplit best;
  std::vector<std::size_t> order(count);
  std::vector<double> left, right;
  for (int a = 0; a < params_.attributes; ++a) {
    const auto attr = [&](std::size_t t) { return n.transitions[t].observation[static_cast<std::size_t>(a)]; };
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return attr(x) < attr(y); });
    for (std::size_t p = min_side; p <= count - min_side; p += stride) {
      const double below = attr(order[p - 1]), above = attr(order[p]);
      if (above - below < params_.min_value_gap) continue;
      left.clear();
      right.clear();
      for (std::size_t k = 0; k < count; ++k) (k < p ? left : right).push_back(n.transitions[order[k]].value);
      std::sort(left.begin(), left.end());
      std::sort(right.begin(), right.end());
      const double d = ks_statistic(left, right);
      if (d > best.statistic) {
        best.attribute = a;
        best.threshold = 0.5 * (below + above);
        best.statistic = d;
        best.critical = ks_critical_value(left.size(), right.size(), params_.ks_alpha);
      }
    }
  }
  if (best.attribute < 0 || best.statistic <= best.critical) return std::nullopt;

  Node left_node, right_node;
  {
    Node& parent = node(leaf);
    left_node.q = right_node.q = parent.q;
    left_node.trace = right_node.trace = parent.trace;
    for (StateTransition& t : parent.transitions)
      (t.observation[static_cast<std::size_t>(best.attribute)] < best.threshold ? left_node : right_node)
          .transitions.push_back(std::move(t));
  }
  best.leaf = leaf;
  best.left = static_cast<int>(nodes_.size());
  best.right = best.left + 1;
  nodes_.push_back(std::move(left_node));
  nodes_.push_back(std::move(right_node));
  Node& parent = node(leaf);  // re-fetched: push_back may have moved the nodes
  parent.attribute = best.attribute;
  parent.threshold = best.threshold;
  parent.left = best.left;
  parent.right = best.right;
  parent.q.clear();
  parent.trace.clear();
  parent.transitions.clear();
  parent.transitions.shrink_to_fit();
  ++leaves_;
  return best;
}


void StateTree::save(BinaryWriter& out) const {
  out.tag("state_tree");
  out.value<std::int32_t>(params_.attributes);
  out.value<std::int32_t>(params_.actions);
  out.value<std::uint64_t>(nodes_.size());
  for (const Node& n : nodes_) {
    out.value<std::int32_t>(n.attribute);
    out.value(n.threshold);
    out.value<std::int32_t>(n.left);
    out.value<std::int32_t>(n.right);
    out.values(n.q);
    out.values(n.trace);
    out.value<std::uint64_t>(n.transitions.size());
    for (const StateTransition& t : n.transitions) {
      out.values(t.observation);
      out.value(t.value);
    }
  }
}

void StateTree::load(BinaryReader& in) {
  in.expect_tag("state_tree");
  const auto attributes = in.value<std::int32_t>("tree attributes");
  const auto actions = in.value<std::int32_t>("tree actions");
  if (attributes != params_.attributes || actions != params_.actions)
    in.fail(fmt::format("state tree over {} attributes and {} actions does not fit this controller's {} and {}",
                        attributes, actions, params_.attributes, params_.actions));
  const auto count = in.value<std::uint64_t>("tree node count");
  if (count < 1 || count > in.remaining()) in.fail(fmt::format("state tree claims {} nodes", count));
  std::vector<Node> nodes(static_cast<std::size_t>(count));
  std::size_t leaves = 0;
  for (Node& n : nodes) {
    n.attribute = in.value<std::int32_t>("tree node attribute");
    n.threshold = in.value<double>("tree node threshold");
    n.left = in.value<std::int32_t>("tree node left");
    n.right = in.value<std::int32_t>("tree node right");
    n.q = in.values<double>("tree Q-values");
    n.trace = in.values<double>("tree traces");
    const auto transitions = in.value<std::uint64_t>("tree transition count");
    if (transitions > in.remaining()) in.fail("state tree claims more transitions than the file holds");
    for (std::uint64_t k = 0; k < transitions; ++k) {
      StateTransition t;
      t.observation = in.values<double>("transition observation");
      t.value = in.value<double>("transition value");
      if (t.observation.size() != static_cast<std::size_t>(attributes)) in.fail("transition of the wrong size");
      n.transitions.push_back(std::move(t));
    }
    const auto inside = [&](int id) { return id > 0 && static_cast<std::uint64_t>(id) < count; };
    if (n.leaf()) {
      ++leaves;
      if (n.q.size() != static_cast<std::size_t>(actions) || n.trace.size() != static_cast<std::size_t>(actions))
        in.fail("state tree leaf without one Q-value and trace per action");
    } else if (n.attribute >= attributes || !inside(n.left) || !inside(n.right)) {
      in.fail("state tree node points outside the tree");
    }
  }
  nodes_ = std::move(nodes);
  leaves_ = leaves;
}

}  // namespace qdmeta
