#include "qdmeta/algorithms/map_elites.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void MapElitesParams::validate() const {
  require(kBatchSize, batch_size);
  require(kInitialPopulation, initial_population);
}

void add_map_elites_memory(MemoryEstimate& m, const MapElitesParams& p, const Task& task) {
  m.add("a generation's offspring", "max(map_elites.initial_population, map_elites.batch_size) x genes",
        offspring_bytes(static_cast<double>(std::max(p.initial_population, p.batch_size)), task));
}

void random_genotypes(RowMatrix& genotypes, Rng& rng) {
  Real* g = genotypes.data();
  for (Index k = 0; k < genotypes.size(); ++k) g[k] = static_cast<Real>(rng.uniform());
}

void check_map_elites_parts(const Task& task, const FeatureMap* feature_map, Index archive_solution_size,
                            Index archive_dimensions) {
  if (!feature_map) throw InputError("map-elites: no feature-map given");
  if (feature_map->input_size() != task.base_feature_size())
    throw InputError(fmt::format("map-elites: the feature-map reads {} base features but task '{}' gives {}",
                                 feature_map->input_size(), task.name(), task.base_feature_size()));
  if (feature_map->output_size() != archive_dimensions)
    throw InputError(fmt::format("map-elites: the feature-map gives {} target features but the archive has {} dimensions",
                                 feature_map->output_size(), archive_dimensions));
  if (archive_solution_size != task.genotype_size())
    throw InputError(fmt::format("map-elites: the archive holds solutions of {} genes but task '{}' has {}",
                                 archive_solution_size, task.name(), task.genotype_size()));
}

template class BasicMapElites<GridArchive>;
template class BasicMapElites<AnyArchive>;

}  // namespace qdmeta
