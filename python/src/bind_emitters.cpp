// CMA-ME and CMA-MAE with pyribs's names (emitters/): qdmeta.EvolutionStrategyEmitter,
// qdmeta.GaussianEmitter, qdmeta.IsoLineEmitter and qdmeta.Scheduler over a GridArchive or CvtArchive whose
// learning_rate and threshold_min give the thresholds. Each emitter asks with its own stream
// (seed=), as pyribs seeds each emitter; all three pickle, and an unpickled scheduler (with its
// archives and emitters, pickled together) continues to the same bits.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "archive_handle.hpp"
#include "bindings.hpp"
#include "emitter_handle.hpp"
#include "numpy_arrays.hpp"
#include "pickled_state.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/emitters/evolution_strategy_emitter.hpp"
#include "qdmeta/emitters/scheduler.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

constexpr int kEmitterStateFormat = 1;  // of the emitter and scheduler state tuples
// The purpose key of an emitter's stream ("EMIT"): apart from sample_elites()'s and the library's.
constexpr std::uint64_t kEmitterStream = 0x454D4954;

// seed=None draws one from the system, as pyribs does; an integer must be in [0, 2^63 - 1].
Rng emitter_stream(py::handle seed) {
  std::uint64_t value = 0;
  if (seed.is_none()) {
    std::random_device device;
    value = (std::uint64_t{device()} << 32 | device()) >> 1;
  } else {
    value = seed_argument(seed);
  }
  return Rng::stream(value, {kEmitterStream});
}

// An integer argument (numpy's too) in the range of `param` (the config key's, core/params.hpp),
// else a one-line error naming the argument.
int integer_argument(py::handle value, const char* name, const IntParam& param) {
  const auto index = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
  if (!index) {
    PyErr_Clear();
    throw py::type_error(fmt::format("{} must be an integer, got {}", name,
                                     py::str(py::type::handle_of(value)).cast<std::string>()));
  }
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0 || v < param.lo || v > param.hi)
    throw InputError(fmt::format("{} = {} is invalid: must be an integer in [{}, {}]", name,
                                 py::str(index).cast<std::string>(), param.lo, param.hi));
  return static_cast<int>(v);
}

// pyribs's ranker names ("imp", "2imp", ... or the class names) and qdmeta's.
std::string ranker_name(const std::string& name) {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> aliases{
      {"improvement", {"imp", "ImprovementRanker"}},
      {"two-stage-improvement", {"2imp", "TwoStageImprovementRanker"}},
      {"objective", {"obj", "ObjectiveRanker"}},
      {"two-stage-objective", {"2obj", "TwoStageObjectiveRanker"}},
      {"random-direction", {"rd", "RandomDirectionRanker"}},
      {"two-stage-random-direction", {"2rd", "TwoStageRandomDirectionRanker"}}};
  for (const auto& [canonical, others] : aliases) {
    if (name == canonical) return canonical;
    for (const auto& other : others)
      if (name == other) return canonical;
  }
  throw InputError(fmt::format("ranker = '{}' is not one of imp, 2imp, obj, 2obj, rd, 2rd", name));
}

// es: pyribs's names ("cma_es", "sep_cma_es" or their class names) and qdmeta's.
std::string es_name(const std::string& name) {
  if (name == "cma_es" || name == "CMAEvolutionStrategy" || name == "cma-es") return "cma-es";
  if (name == "sep_cma_es" || name == "SeparableCMAEvolutionStrategy" || name == "sep-cma-es") return "sep-cma-es";
  throw InputError(fmt::format("es = '{}' is not 'cma_es' or 'sep_cma_es' (qdmeta has no other evolution strategy)",
                               name));
}

// restart_rule: "no_improvement", "basic" or an integer n (restart every n iterations).
std::pair<std::string, int> restart_rule(py::handle rule) {
  if (!py::isinstance<py::str>(rule) && !py::isinstance<py::bool_>(rule) && PyIndex_Check(rule.ptr()))
    return {"every-n", integer_argument(rule, "restart_rule", EvolutionStrategyEmitterParams::kRestartEvery)};
  const std::string name = py::str(rule).cast<std::string>();
  if (py::isinstance<py::str>(rule) && name == "no_improvement") return {"no-improvement", 0};
  if (py::isinstance<py::str>(rule) && name == "basic") return {"basic", 0};
  throw InputError(fmt::format("restart_rule = {} is not 'no_improvement', 'basic' or an integer >= 1",
                               py::repr(rule).cast<std::string>()));
}

int batch_size_argument(py::handle batch_size, int otherwise) {
  return batch_size.is_none() ? otherwise : integer_argument(batch_size, "batch_size", kEmitterBatchSize);
}

// pyribs's bounds (one (lower, upper) pair per gene, or None); qdmeta's emitters clamp every gene
// to one range, so the pairs must agree.
std::pair<double, double> common_gene_bounds(py::handle bounds, Index genes) {
  const double inf = std::numeric_limits<double>::infinity();
  if (bounds.is_none()) return {-inf, inf};
  const auto pairs = bounds.cast<std::vector<std::pair<std::optional<double>, std::optional<double>>>>();
  if (static_cast<Index>(pairs.size()) != genes)
    throw InputError(fmt::format("bounds has {} pairs; the archive's solution_dim is {}", pairs.size(), genes));
  const auto lower = [&](std::size_t i) { return pairs[i].first.value_or(-inf); };
  const auto upper = [&](std::size_t i) { return pairs[i].second.value_or(inf); };
  for (std::size_t i = 1; i < pairs.size(); ++i)
    if (lower(i) != lower(0) || upper(i) != upper(0))
      throw InputError("bounds differ between genes: qdmeta's Gaussian and iso+line emitters clamp every gene to one range");
  return {lower(0), upper(0)};
}

py::tuple emitter_state(const EmitterHandle& h) {
  BinaryWriter out;
  h.save(out);
  const py::int_ format(kEmitterStateFormat);
  const py::str kind(h.kind);
  const py::bytes bytes(out.bytes());
  const py::int_ checksum(state_checksum({format, kind, h.parameters, bytes}));
  return py::make_tuple(format, kind, h.archive, h.parameters, bytes, checksum);
}

template <class H>
std::shared_ptr<H> emitter_from_state(const py::tuple& s) {
  const char* who = "unpickling a qdmeta emitter";
  if (s.size() != 6 || !py::reinterpret_borrow<py::object>(s[0]).equal(py::int_(kEmitterStateFormat)) ||
      !py::isinstance<py::str>(s[1]) || !py::isinstance<py::tuple>(s[3]) || !py::isinstance<py::bytes>(s[4]))
    throw InputError(fmt::format("{}: the state is not one qdmeta made", who));
  check_state_checksum(s[5], state_checksum({s[0], s[1], s[3], s[4]}), who);
  auto h = std::make_shared<H>();
  build_emitter(*h, py::reinterpret_borrow<py::object>(s[2]), s[1].cast<std::string>(), s[3], Rng{});
  const std::string bytes = s[4].cast<std::string>();
  BinaryReader in(bytes, "the pickled emitter");
  h->load(in);
  in.finish();
  return h;
}

template <class H, class Class>
void bind_emitter_pickle(Class& c) {
  c.def(py::pickle([](const H& h) { return emitter_state(h); },
                   [](const py::tuple& s) { return emitter_from_state<H>(s); }));
}

// A new emitter of `kind` (the constructors' arguments already in qdmeta's terms).
template <class H>
std::shared_ptr<H> new_emitter(py::object archive, const char* kind, py::tuple parameters, py::handle seed) {
  auto h = std::make_shared<H>();
  build_emitter(*h, std::move(archive), kind, std::move(parameters), emitter_stream(seed));
  return h;
}

}  // namespace

void bind_emitters(py::module_& m) {
  py::class_<EmitterHandle, std::shared_ptr<EmitterHandle>>(m, "Emitter", "What the emitters share")
      .def_property_readonly("archive", [](const EmitterHandle& h) { return h.archive; })
      .def_property_readonly("batch_size", [](const EmitterHandle& h) { return h.emitter->batch_size(); });

  using EsHandle = EvolutionStrategyEmitterHandle;
  py::class_<EsHandle, EmitterHandle, std::shared_ptr<EsHandle>> es(m, "EvolutionStrategyEmitter", R"doc(
CMA-ME's emitter, as pyribs's EvolutionStrategyEmitter: CMA-ES proposes each batch; told how the
archive took it, the emitter ranks the rows (ranker "2imp", "imp", "obj", "2obj", "rd", "2rd"),
takes the parents (selection_rule "filter": the rows the archive took; "mu": the best half) and
restarts CMA-ES from a random elite when restart_rule fires ("no_improvement", "basic" or every n
iterations) or CMA-ES converges. es "cma_es" is the full CMA-ES, "sep_cma_es" the separable one
(diagonal covariance, for large solution_dim); es_kwargs must be None. batch_size None is CMA-ES's
4 + floor(3 ln solution_dim); seed None draws one from the system. bounds must be None (qdmeta's
CMA-ES here is unbounded).)doc");
  es.def(py::init([](py::object archive, py::handle x0, double sigma0, const std::string& ranker,
                     const std::string& es_value, py::handle es_kwargs, const std::string& selection_rule,
                     py::handle restart_rule_value, py::handle bounds, py::handle batch_size, py::handle seed) {
           if (!bounds.is_none()) throw InputError("bounds must be None: qdmeta's EvolutionStrategyEmitter is unbounded");
           if (!es_kwargs.is_none()) throw InputError("es_kwargs must be None: qdmeta's evolution strategies take no options");
           if (selection_rule != "filter" && selection_rule != "mu")
             throw InputError(fmt::format("selection_rule = '{}' is not 'filter' or 'mu'", selection_rule));
           const Index genes = archive_solution_dim(archive);
           const auto [restart, every] = restart_rule(restart_rule_value);
           const int lambda = 4 + static_cast<int>(std::floor(3.0 * std::log(static_cast<double>(genes))));
           return new_emitter<EsHandle>(archive, "EvolutionStrategyEmitter",
                                        py::make_tuple(x0, sigma0, batch_size_argument(batch_size, lambda),
                                                       ranker_name(ranker), selection_rule, restart, every,
                                                       es_name(es_value)),
                                        seed);
         }),
         py::arg("archive"), py::kw_only(), py::arg("x0"), py::arg("sigma0"), py::arg("ranker") = "2imp",
         py::arg("es") = "cma_es", py::arg("es_kwargs") = py::none(), py::arg("selection_rule") = "filter", py::arg("restart_rule") = "no_improvement",
         py::arg("bounds") = py::none(), py::arg("batch_size") = py::none(), py::arg("seed") = py::none())
      .def_property_readonly("restarts",
                             [](const EsHandle& h) {
                               return static_cast<const EvolutionStrategyEmitter&>(*h.emitter).restarts();
                             },
                             "How many times CMA-ES has restarted")
      .def_property_readonly("itrs",
                             [](const EsHandle& h) {
                               return static_cast<const EvolutionStrategyEmitter&>(*h.emitter).tells();
                             },
                             "How many batches the emitter has been told");
  bind_emitter_pickle<EsHandle>(es);

  py::class_<GaussianEmitterHandle, EmitterHandle, std::shared_ptr<GaussianEmitterHandle>> gaussian(
      m, "GaussianEmitter", R"doc(
MAP-Elites's variation as an emitter, as pyribs's GaussianEmitter: each row is a random elite plus
N(0, sigma^2) per gene (x0 plus that noise while the archive is empty), clamped to bounds (one
(lower, upper) pair per gene, all equal here, or None). seed None draws one from the system.)doc");
  gaussian
      .def(py::init([](py::object archive, double sigma, py::handle x0, py::handle bounds, py::handle batch_size,
                       py::handle seed) {
             if (x0.is_none()) throw InputError("x0 is None: give the first parent, one value per gene");
             const auto [lower, upper] = common_gene_bounds(bounds, archive_solution_dim(archive));
             return new_emitter<GaussianEmitterHandle>(
                 archive, "GaussianEmitter", py::make_tuple(x0, sigma, batch_size_argument(batch_size, 64), lower, upper),
                 seed);
           }),
           py::arg("archive"), py::kw_only(), py::arg("sigma"), py::arg("x0") = py::none(),
           py::arg("bounds") = py::none(), py::arg("batch_size") = 64, py::arg("seed") = py::none());
  bind_emitter_pickle<GaussianEmitterHandle>(gaussian);

  py::class_<IsoLineEmitterHandle, EmitterHandle, std::shared_ptr<IsoLineEmitterHandle>> iso_line(
      m, "IsoLineEmitter", R"doc(
The iso+line operator (Vassiliades & Mouret 2018) as an emitter, as pyribs's IsoLineEmitter: each
row is x_i + iso_sigma N(0, I) + line_sigma N(0, 1) (x_j - x_i) for two random elites x_i, x_j
(x0 plus the isotropic noise while the archive is empty), clamped to bounds (one (lower, upper)
pair per gene, all equal here, or None). seed None draws one from the system.)doc");
  iso_line
      .def(py::init([](py::object archive, double iso_sigma, double line_sigma, py::handle x0, py::handle bounds,
                       py::handle batch_size, py::handle seed) {
             if (x0.is_none()) throw InputError("x0 is None: give the first parent, one value per gene");
             const auto [lower, upper] = common_gene_bounds(bounds, archive_solution_dim(archive));
             return new_emitter<IsoLineEmitterHandle>(
                 archive, "IsoLineEmitter",
                 py::make_tuple(x0, iso_sigma, line_sigma, batch_size_argument(batch_size, 64), lower, upper), seed);
           }),
           py::arg("archive"), py::kw_only(), py::arg("iso_sigma") = 0.01, py::arg("line_sigma") = 0.2,
           py::arg("x0") = py::none(), py::arg("bounds") = py::none(), py::arg("batch_size") = 64,
           py::arg("seed") = py::none());
  bind_emitter_pickle<IsoLineEmitterHandle>(iso_line);

}

}  // namespace qdmeta::python
