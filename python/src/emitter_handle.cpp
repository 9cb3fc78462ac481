#include "emitter_handle.hpp"

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <vector>

#include "archive_handle.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/emitters/evolution_strategy_emitter.hpp"
#include "qdmeta/emitters/gaussian_emitter.hpp"
#include "qdmeta/emitters/iso_line_emitter.hpp"
#include "qdmeta/emitters/scheduler.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

ElitePicker picker_of(py::handle archive) {
  if (py::isinstance<ArchiveHandle<GridArchive>>(archive))
    return elite_picker(archive.cast<ArchiveHandle<GridArchive>&>().archive);
  if (py::isinstance<ArchiveHandle<CvtArchive>>(archive))
    return elite_picker(archive.cast<ArchiveHandle<CvtArchive>&>().archive);
  throw py::type_error(fmt::format("archive must be a qdmeta.GridArchive or qdmeta.CvtArchive, got {}",
                                   py::str(py::type::handle_of(archive)).cast<std::string>()));
}

// x0 checked against the archive: one value per gene.
std::vector<double> x0_of(py::handle archive, py::handle x0) {
  const auto values = x0.cast<std::vector<double>>();
  const Index genes = archive_solution_dim(archive);
  if (static_cast<Index>(values.size()) != genes)
    throw InputError(fmt::format("x0 has {} values; the archive's solution_dim is {}", values.size(), genes));
  return values;
}

}  // namespace

Index archive_solution_dim(py::handle archive) {
  if (py::isinstance<ArchiveHandle<GridArchive>>(archive))
    return archive.cast<ArchiveHandle<GridArchive>&>().archive.solution_size();
  if (py::isinstance<ArchiveHandle<CvtArchive>>(archive))
    return archive.cast<ArchiveHandle<CvtArchive>&>().archive.solution_size();
  picker_of(archive);  // throws the TypeError
  return 0;
}

std::vector<double> archive_measure_ranges(py::handle archive) {
  if (py::isinstance<ArchiveHandle<GridArchive>>(archive)) {
    const GridArchiveParams& p = archive.cast<ArchiveHandle<GridArchive>&>().archive.params();
    std::vector<double> ranges;
    for (std::size_t d = 0; d < p.bins.size(); ++d) ranges.push_back(p.upper_of(d) - p.lower_of(d));
    return ranges;
  }
  if (py::isinstance<ArchiveHandle<CvtArchive>>(archive))
    return std::vector<double>(static_cast<std::size_t>(archive.cast<ArchiveHandle<CvtArchive>&>().archive.dimensions()), 1.0);
  picker_of(archive);
  return {};
}

void build_emitter(EmitterHandle& h, py::object archive, const std::string& kind, py::tuple v, Rng rng) {
  ElitePicker picker = picker_of(archive);
  // 8 parameters, the last the evolution strategy; 7 (pickles from before es) is the full CMA-ES.
  if (kind == "EvolutionStrategyEmitter" && (v.size() == 7 || v.size() == 8)) {
    EvolutionStrategyEmitterParams p;
    p.x0 = x0_of(archive, v[0]);
    p.sigma0 = v[1].cast<double>();
    p.batch_size = v[2].cast<int>();
    p.ranker = emitter_ranker_from_string(v[3].cast<std::string>());
    p.selection = emitter_selection_from_string(v[4].cast<std::string>());
    p.restart = emitter_restart_from_string(v[5].cast<std::string>());
    p.restart_every = v[6].cast<int>();
    if (v.size() == 8) p.es = evolution_strategy_kind_from_string(v[7].cast<std::string>());
    if (needs_direction(p.ranker)) p.measure_ranges = archive_measure_ranges(archive);
    p.validate();
    h.emitter = std::make_unique<EvolutionStrategyEmitter>(std::move(p), std::move(picker));
  } else if (kind == "GaussianEmitter" && v.size() == 5) {
    GaussianEmitterParams p;
    p.x0 = x0_of(archive, v[0]);
    p.sigma = v[1].cast<double>();
    p.batch_size = v[2].cast<int>();
    p.lower_bound = v[3].cast<double>();
    p.upper_bound = v[4].cast<double>();
    p.validate();
    h.emitter = std::make_unique<GaussianEmitter>(std::move(p), std::move(picker));
  } else if (kind == "IsoLineEmitter" && v.size() == 6) {
    IsoLineEmitterParams p;
    p.x0 = x0_of(archive, v[0]);
    p.iso_sigma = v[1].cast<double>();
    p.line_sigma = v[2].cast<double>();
    p.batch_size = v[3].cast<int>();
    p.lower_bound = v[4].cast<double>();
    p.upper_bound = v[5].cast<double>();
    p.validate();
    h.emitter = std::make_unique<IsoLineEmitter>(std::move(p), std::move(picker));
  } else {
    throw InputError(fmt::format("build_emitter: no emitter {} of {} parameters", kind, v.size()));
  }
  h.archive = std::move(archive);
  h.kind = kind;
  h.parameters = std::move(v);
  h.rng = rng;
}

void EmitterHandle::save(BinaryWriter& out) const {
  out.tag("python emitter");
  const Rng::State s = rng.state();
  for (const std::uint64_t word : s.words) out.value(word);
  out.boolean(s.has_spare);
  out.value(s.spare);
  out.boolean(s.has_spare_float);
  out.value(s.spare_float);
  emitter->save(out);
}

void EmitterHandle::load(BinaryReader& in) {
  in.expect_tag("python emitter");
  Rng::State s;
  for (std::uint64_t& word : s.words) word = in.value<std::uint64_t>("emitter stream");
  s.has_spare = in.boolean("emitter stream");
  s.spare = in.value<double>("emitter stream");
  s.has_spare_float = in.boolean("emitter stream");
  s.spare_float = in.value<float>("emitter stream");
  emitter->load(in);
  rng.set_state(s);
}

}  // namespace qdmeta::python
