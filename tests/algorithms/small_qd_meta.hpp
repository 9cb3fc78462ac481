#pragma once
// The small QD-Meta of the algorithm tests: 6-D Rastrigin, 4 maps of 20 x 20 cells, batches of 50,
// 200 seeds, a database of 3,000, the Translation meta-fitness on half of each archive.
#include <cstdint>
#include <memory>
#include <utility>

#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace qdmeta {

inline QdMetaParams small_qd_meta_params() {
  QdMetaParams p;
  p.meta_population = 4;
  p.batch_size = 50;
  p.initial_population = 200;
  p.database_capacity = 3000;
  return p;
}

// `objective` null: Translation on half of each archive.
inline QdMeta small_qd_meta_of(const QdMetaParams& p, std::uint64_t seed, std::unique_ptr<GenerationController> control,
                               std::unique_ptr<MetaObjective> objective = nullptr) {
  RastriginParams rp;
  rp.dimensions = 6;
  GridArchiveParams grid;
  grid.bins = {20, 20};
  RastriginMetaParams mp;
  mp.sample_fraction = 0.5;
  if (!objective) objective = std::make_unique<RastriginTranslationMeta>(mp);
  return QdMeta(p, Task(RastriginTask(rp)), std::move(objective), grid, {}, std::move(control), seed);
}

}  // namespace qdmeta
