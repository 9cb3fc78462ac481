#include "algorithm_archive.hpp"

#include <fmt/format.h>

#include "archive_handle.hpp"
#include "archive_queries.hpp"
#include "qdmeta/algorithms/aurora.hpp"
#include "qdmeta/algorithms/cma_mae.hpp"
#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// The archive the first step would make (CVT's centroids: the same bits on any number of threads).
template <class A>
const auto& prepared_archive(A& algorithm) {
  if (!algorithm.prepared()) {
    const py::gil_scoped_release release;
    const auto evaluator = make_evaluator(0);
    algorithm.prepare(*evaluator);
  }
  return algorithm.archive();
}

// f(the algorithm's archive), whichever of the built-in algorithms' archives it is.
template <class F>
auto with_archive(Algorithm& algorithm, F&& f) {
  if (const auto* me = dynamic_cast<const MapElites*>(&algorithm)) return f(me->archive());
  if (auto* cvt = dynamic_cast<CvtMapElites*>(&algorithm)) return f(prepared_archive(*cvt));
  if (auto* emitters = dynamic_cast<CmaMae<GridArchive>*>(&algorithm)) return f(prepared_archive(*emitters));
  if (auto* emitters = dynamic_cast<CmaMae<CvtArchive>*>(&algorithm)) return f(prepared_archive(*emitters));
  if (const auto* aurora = dynamic_cast<const Aurora*>(&algorithm)) return f(aurora->archive());
  if (const auto* qd_meta = dynamic_cast<const QdMeta*>(&algorithm)) return f(qd_meta->best_archive());
  throw Error(fmt::format("{}: this algorithm keeps no archive that qdmeta can show", algorithm.name()));
}

}  // namespace

py::object archive_copy(Algorithm& algorithm, std::uint64_t seed) {
  return with_archive(algorithm, [seed](const auto& archive) {
    using Archive = std::remove_cvref_t<decltype(archive)>;
    return py::cast(ArchiveHandle<Archive>(archive, seed));
  });
}

py::tuple retrieve_from(Algorithm& algorithm, py::handle measures) {
  return with_archive(algorithm, [measures](const auto& archive) { return retrieve(archive, measures); });
}

}  // namespace qdmeta::python
