#pragma once
// [control] kind = "cycle": QD-Meta's meta-generations run G = g1, g2, ..., gn, g1, ... generations,
// the list `generations` of the config, in turn (a schedule fixed in advance, where "static" fixes
// one G and "sarsa" learns it). docs/tutorials/controller.md builds it.
#include <qdmeta/control/controller.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace qdmeta {
class ConfigReader;
}

namespace arm {

class CycleControl final : public qdmeta::GenerationController {
 public:
  explicit CycleControl(std::vector<int> generations);  // each >= 1, at least one
  std::string name() const override { return "cycle"; }
  int choose_generations(const Eigen::MatrixXd& samples, qdmeta::Rng& rng) override;
  int max_generations() const override;
  void observe(std::span<const double> meta_fitness, std::int64_t evaluations) override;
  void save(qdmeta::BinaryWriter& out) const override;
  void load(qdmeta::BinaryReader& in) override;

 private:
  std::vector<int> generations_;
  std::size_t next_ = 0;  // the entry the next meta-generation runs
};

// [control] kind = "cycle": key `generations` (1 to 100 entries, each in [1, 1000]; default [1, 5]).
std::unique_ptr<qdmeta::GenerationController> read_cycle_control(qdmeta::ConfigReader& control);

// Makes `[control] kind = "cycle"` available to configs (qdmeta's controller registry).
void register_cycle_control();

}  // namespace arm
