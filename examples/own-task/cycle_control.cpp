#include "cycle_control.hpp"

#include <qdmeta/core/error.hpp>
#include <qdmeta/plugin/config.hpp>
#include <qdmeta/plugin/part_registries.hpp>

#include <algorithm>
#include <utility>

namespace arm {

CycleControl::CycleControl(std::vector<int> generations) : generations_(std::move(generations)) {
  if (generations_.empty() || *std::min_element(generations_.begin(), generations_.end()) < 1)
    throw qdmeta::InputError("control kind \"cycle\": generations must hold at least one entry, each >= 1");
}

// The schedule ignores the sampled meta-genotypes and draws nothing: G depends only on how many
// meta-generations came before, which the checkpoint keeps (next_).
int CycleControl::choose_generations(const Eigen::MatrixXd& /*samples*/, qdmeta::Rng& /*rng*/) {
  const int g = generations_[next_];
  next_ = (next_ + 1) % generations_.size();
  return g;
}

int CycleControl::max_generations() const { return *std::max_element(generations_.begin(), generations_.end()); }

// A fixed schedule learns nothing from the meta-fitness.
void CycleControl::observe(std::span<const double> /*meta_fitness*/, std::int64_t /*evaluations*/) {}

// What a resumed run needs to act as the uninterrupted one: the position in the schedule (the
// schedule itself comes from the config, which the checkpoint's fingerprint pins).
void CycleControl::save(qdmeta::BinaryWriter& out) const {
  out.tag("cycle_control");
  out.value(static_cast<std::uint64_t>(next_));
}

void CycleControl::load(qdmeta::BinaryReader& in) {
  in.expect_tag("cycle_control");
  const auto next = in.value<std::uint64_t>("next entry");
  if (next >= generations_.size()) throw qdmeta::Error("control kind \"cycle\": the checkpoint's entry is past the list");
  next_ = static_cast<std::size_t>(next);
}

std::unique_ptr<qdmeta::GenerationController> read_cycle_control(qdmeta::ConfigReader& control) {
  const auto entries = control.integers("generations", {1, 5}, 1, 1000, 1, 100);
  return std::make_unique<CycleControl>(std::vector<int>(entries.begin(), entries.end()));
}

void register_cycle_control() { qdmeta::controller_registry().add("cycle", read_cycle_control); }

}  // namespace arm
