// qdmeta.GridArchive, qdmeta.CvtArchive (with qdmeta.cvt_centroids, cached as the CLI caches
// them) and qdmeta.UnstructuredArchive: batch add returning statuses, statistics with pyribs's
// names, the elites as numpy arrays, one by one (iteration), by measures (retrieve) or drawn
// at random (sample_elites); pickle, copy and deepcopy.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "archive_handle.hpp"
#include "archive_pickle.hpp"
#include "archive_queries.hpp"
#include "bindings.hpp"
#include "elite_arrays.hpp"
#include "numpy_arrays.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/archive/kmeans.hpp"
#include "qdmeta/archive/unstructured_archive.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/io/centroid_cache.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// The arrays of one add() call, checked and converted (views when already float32 and
// C-contiguous); rows = the solutions' row count.
struct AddArguments {
  FloatArray solutions, objectives, measures, base_features;
  std::optional<ByteArray> valid;
  Index rows = 0;
  bool has_base_features = false;

  AddArguments(py::handle s, py::handle o, py::handle m, py::handle b, py::handle v, Index solution_size,
               Index measure_size, Index base_feature_size) {
    solutions = float_rows(s, -1, solution_size, "solutions");
    rows = solutions.shape(0);
    objectives = float_rows(o, rows, -1, "objectives");
    measures = float_rows(m, rows, measure_size, "measures");
    if (base_feature_size > 0) {
      if (b.is_none())
        throw py::value_error(fmt::format("base_features: this archive keeps {} per elite; give an array ({}, {})",
                                          base_feature_size, rows, base_feature_size));
      base_features = float_rows(b, rows, base_feature_size, "base_features");
      has_base_features = true;
    }
    if (!v.is_none()) valid = flags(v, rows, "valid");
  }

  EliteBatch batch() const {
    EliteBatch e;
    e.solutions = {solutions.data(), rows, solutions.shape(1)};
    e.objectives = {objectives.data(), static_cast<std::size_t>(rows)};
    e.measures = {measures.data(), rows, measures.shape(1)};
    if (has_base_features) e.base_features = {base_features.data(), rows, base_features.shape(1)};
    if (valid) e.valid = {valid->data(), static_cast<std::size_t>(rows)};
    return e;
  }
};

py::array_t<std::uint8_t> statuses(const std::vector<AddStatus>& s) {
  py::array_t<std::uint8_t> out = new_array<std::uint8_t>({static_cast<py::ssize_t>(s.size())});
  for (std::size_t i = 0; i < s.size(); ++i) out.mutable_data()[i] = static_cast<std::uint8_t>(s[i]);
  return out;
}

const char* kAddDoc =
    "add(solutions, objectives, measures, base_features=None, valid=None) -> statuses: a uint8 array, one per "
    "row: 0 not added, 1 improved an elite, 2 filled a new cell. Rows go in in order, as if added one by one.";

// What every archive class offers besides add(): the queries of archive_queries.hpp, its
// seed, pickling (archive_pickle.hpp), copy and deepcopy (the archive holds no Python objects,
// so both are a C++ copy).
template <class Archive, class Class>
void bind_common(Class& c, EliteTable (*elites)(const Archive&)) {
  using Handle = ArchiveHandle<Archive>;
  c.def("retrieve", [](const Handle& h, py::handle m) { return retrieve(h.archive, m); }, py::arg("measures"),
        "retrieve(measures (n, measure_dim)) -> (occupied (n,) bool, {index, objective, measures, solution}): the "
        "elite at each row's measures, as pyribs's retrieve(); a row with none has index -1 and NaN fields")
      .def("retrieve_single", [](const Handle& h, py::handle m) { return retrieve_single(h.archive, m); },
           py::arg("measures"), "retrieve() for one measure vector: (occupied, {index, objective, measures, solution})")
      .def(
          "sample_elites",
          [](Handle& h, Index n, bool replace) { return sample_elites(h.archive, h.next_sample_stream(), n, replace); },
          py::arg("n"), py::arg("replace") = true,
          "n elites drawn uniformly from the archive (with replacement unless replace=False), as {index, objective, "
          "measures, solution} arrays. Call k draws from the stream (seed, k): the same archive and seed give the "
          "same samples, also after pickling")
      .def("__iter__", [elites](const Handle& h) { return iterate_elites(elites(h.archive)); },
           "One dict per elite (solution, objective, measures, index), in cell order, from a snapshot")
      .def_property_readonly("qd_score_offset", [](const Handle& h) { return h.archive.params().qd_offset; },
                             "pyribs's name for qd_offset: qd_score sums objective - qd_score_offset")
      .def_property_readonly("seed", [](const Handle& h) { return h.seed; },
                             "The seed of sample_elites()'s random streams")
      .def("__copy__", [](const Handle& h) { return h; })
      .def("__deepcopy__", [](const Handle& h, const py::object&) { return h; }, py::arg("memo"))
      .def(py::pickle([](const Handle& h) { return archive_state(h); },
                      [](const py::tuple& state) { return archive_from_state<Archive>(state); }));
}

template <class Archive, class Class>
void bind_elite_archive(Class& c) {
  using Handle = ArchiveHandle<Archive>;
  c.def(
       "add",
       [](Handle& h, py::handle s, py::handle o, py::handle m, py::handle b, py::handle v) {
         Archive& a = h.archive;
         const AddArguments args(s, o, m, b, v, a.solution_size(), a.dimensions(), a.base_feature_size());
         std::vector<AddStatus> status(static_cast<std::size_t>(args.rows));
         {
           const py::gil_scoped_release release;
           a.add_batch(args.batch(), status);
         }
         return statuses(status);
       },
       py::arg("solutions"), py::arg("objectives"), py::arg("measures"), py::arg("base_features") = py::none(),
       py::arg("valid") = py::none(), kAddDoc)
      .def_property_readonly("stats", [](const Handle& h) { return h.archive.stats(); })
      .def_property_readonly("cells", [](const Handle& h) { return h.archive.cells(); })
      .def_property_readonly("solution_dim", [](const Handle& h) { return h.archive.solution_size(); })
      .def_property_readonly("measure_dim", [](const Handle& h) { return h.archive.dimensions(); })
      .def("__len__", [](const Handle& h) { return h.archive.size(); })
      .def("clear", [](Handle& h) { h.archive.clear(); })
      .def(
          "index_of",
          [](const Handle& h, py::handle measures) {
            const Archive& a = h.archive;
            const FloatArray v = measure_rows(measures, -1, a.dimensions());
            py::array_t<std::int64_t> out = new_array<std::int64_t>({v.shape(0)});
            for (py::ssize_t i = 0; i < v.shape(0); ++i)
              out.mutable_data()[i] = a.index_of(v.data() + i * a.dimensions());
            return out;
          },
          py::arg("measures"), "The cell index of each row of measures")
      .def("data", [](const Handle& h) { return elite_table_data(h.archive.elites()); },
           "The elites as numpy arrays: index, objective, measures, solution (and base_features), by cell index")
      .def("as_pandas", [](const Handle& h) { return elite_table_pandas(h.archive.elites()); },
           "The elites as a pandas DataFrame with pyribs's columns: index, objective, measures_0.., solution_0..");
  bind_common<Archive>(c, +[](const Archive& a) { return a.elites(); });
}

// learning_rate and threshold_min as properties (pyribs's names) on the archives that take them.
template <class Archive, class Class>
void bind_thresholds(Class& c) {
  c.def_property_readonly("learning_rate", [](const ArchiveHandle<Archive>& h) { return h.thresholds.alpha; },
                          "CMA-MAE's alpha: how far a cell's threshold moves toward an accepted objective (1: CMA-ME)")
      .def_property_readonly("threshold_min", [](const ArchiveHandle<Archive>& h) { return h.thresholds.threshold_min; },
                             "The threshold of a cell never reached (-inf: CMA-ME)");
}

}  // namespace

// A seed argument: any Python integer (numpy's too) in the config's range [0, 2^63 - 1], else a
// one-line error naming it (pybind11's own would list every overload).
std::uint64_t seed_argument(py::handle value) {
  const auto index = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
  if (!index) {
    PyErr_Clear();
    throw py::type_error(
        fmt::format("seed must be an integer, got {}", py::str(py::type::handle_of(value)).cast<std::string>()));
  }
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0 || v < 0)
    throw InputError(fmt::format("seed = {} is out of range: must be in [0, {}]", py::str(index).cast<std::string>(),
                                 std::numeric_limits<std::int64_t>::max()));
  return static_cast<std::uint64_t>(v);
}

ThresholdParams threshold_arguments(py::handle learning_rate, double threshold_min) {
  ThresholdParams t;
  if (!learning_rate.is_none()) t.alpha = learning_rate.cast<double>();
  if (!(t.alpha >= 0.0 && t.alpha <= 1.0))
    throw InputError(fmt::format("learning_rate = {} is outside [0, 1] (CMA-MAE's alpha)", t.alpha));
  if (std::isnan(threshold_min) || threshold_min == std::numeric_limits<double>::infinity())
    throw InputError(fmt::format("threshold_min = {} is invalid: must be a number or -inf", threshold_min));
  if (std::isinf(threshold_min) && t.alpha != 1.0)
    throw InputError(fmt::format("threshold_min = -inf needs learning_rate = 1 (got {}): give a finite threshold_min "
                                 "for CMA-MAE",
                                 t.alpha));
  t.threshold_min = threshold_min;
  t.validate();
  return t;
}

void bind_archives(py::module_& m) {
  py::class_<ArchiveStats>(m, "ArchiveStats", "An archive's statistics, with pyribs's names and meanings")
      .def_readonly("num_elites", &ArchiveStats::num_elites)
      .def_readonly("coverage", &ArchiveStats::coverage)
      .def_readonly("qd_score", &ArchiveStats::qd_score)
      .def_readonly("norm_qd_score", &ArchiveStats::norm_qd_score)
      .def_readonly("obj_max", &ArchiveStats::obj_max)
      .def_readonly("obj_mean", &ArchiveStats::obj_mean)
      .def("as_dict",
           [](const ArchiveStats& s) {
             py::dict d;
             d["num_elites"] = s.num_elites;
             d["coverage"] = s.coverage;
             d["qd_score"] = s.qd_score;
             d["norm_qd_score"] = s.norm_qd_score;
             d["obj_max"] = s.obj_max;
             d["obj_mean"] = s.obj_mean;
             return d;
           })
      .def("__repr__", [](const ArchiveStats& s) {
        return fmt::format("ArchiveStats(num_elites={}, coverage={:.6g}, qd_score={:.6g}, norm_qd_score={:.6g}, "
                           "obj_max={:.6g}, obj_mean={:.6g})",
                           s.num_elites, s.coverage, s.qd_score, s.norm_qd_score, s.obj_max, s.obj_mean);
      });
  bind_elite_iterator(m);

  py::class_<ArchiveHandle<GridArchive>> grid(m, "GridArchive", R"doc(
A MAP-Elites grid: `dims` bins per measure, every measure over [lower, upper], or measure i over
ranges[i] = (lower_i, upper_i) as pyribs's `ranges` (values outside go to the edge bins), one elite per cell, replaced only by a strictly better objective; cells
numbered in row-major order as pyribs's GridArchive. `seed` seeds sample_elites().
learning_rate and threshold_min are CMA-MAE's (pyribs's names): a Scheduler over this archive
keeps one threshold per cell with them; the archive itself always keeps each cell's best elite.)doc");
  grid.def(py::init([](Index solution_dim, std::vector<int> dims, double lower, double upper, double qd_offset,
                       Index base_feature_dim, py::handle seed, std::optional<std::vector<std::pair<double, double>>> ranges,
                       py::handle learning_rate, double threshold_min) {
             GridArchiveParams p;
             p.bins = std::move(dims);
             p.lower = lower;
             p.upper = upper;
             if (ranges) {
               if (lower != 0.0 || upper != 1.0)
                 throw py::value_error("GridArchive(): give ranges= or lower=/upper=, not both");
               for (const auto& [lo, hi] : *ranges) {
                 p.lower_bounds.push_back(lo);
                 p.upper_bounds.push_back(hi);
               }
             }
             p.solution_size = solution_dim;
             p.qd_offset = qd_offset;
             p.base_feature_size = base_feature_dim;
             p.validate();
             ArchiveHandle<GridArchive> h(GridArchive(p), seed_argument(seed));
             h.thresholds = threshold_arguments(learning_rate, threshold_min);
             return h;
           }),
           py::arg("solution_dim"), py::arg("dims"), py::arg("lower") = 0.0, py::arg("upper") = 1.0,
           py::arg("qd_offset") = 0.0, py::arg("base_feature_dim") = 0, py::arg("seed") = kDefaultArchiveSeed,
           py::arg("ranges") = py::none(), py::arg("learning_rate") = py::none(),
           py::arg("threshold_min") = -std::numeric_limits<double>::infinity());
  bind_elite_archive<GridArchive>(grid);
  bind_thresholds<GridArchive>(grid);
  grid.def_property_readonly("dims", [](const ArchiveHandle<GridArchive>& h) { return h.archive.params().bins; })
      .def_property_readonly("lower", [](const ArchiveHandle<GridArchive>& h) { return common_bound(h.archive.params(), false); })
      .def_property_readonly("upper", [](const ArchiveHandle<GridArchive>& h) { return common_bound(h.archive.params(), true); })
      // pyribs's names: one bound per measure (qdmeta.visualize draws from them).
      .def_property_readonly("lower_bounds", [](const ArchiveHandle<GridArchive>& h) { return bounds_of(h.archive.params(), false); })
      .def_property_readonly("upper_bounds", [](const ArchiveHandle<GridArchive>& h) { return bounds_of(h.archive.params(), true); });

  py::class_<ArchiveHandle<CvtArchive>> cvt(m, "CvtArchive", R"doc(
A CVT-MAP-Elites archive: one cell per centroid (a (cells x measure_dim) array, e.g. from
qdmeta.cvt_centroids), a measure vector belongs to its nearest centroid's cell (exact; ties to
the lower index). `seed` seeds sample_elites().)doc");
  cvt.def(py::init([](Index solution_dim, py::handle centroids, double qd_offset, py::handle seed, py::handle learning_rate,
                      double threshold_min) {
            const py::array a = py::array::ensure(centroids);
            if (!a || a.ndim() != 2 || a.shape(0) < 1 || a.shape(1) < 1)
              throw py::value_error("centroids must be a 2-D array (cells, measure_dim) with at least one row");
            const FloatArray f = float_rows(centroids, a.shape(0), a.shape(1), "centroids");
            RowMatrix rows = Eigen::Map<const RowMatrix>(f.data(), f.shape(0), f.shape(1));
            ArchiveHandle<CvtArchive> h(CvtArchive(CvtArchiveParams{solution_dim, qd_offset, 0}, std::move(rows)),
                                        seed_argument(seed));
            h.thresholds = threshold_arguments(learning_rate, threshold_min);
            return h;
          }),
          py::arg("solution_dim"), py::arg("centroids"), py::arg("qd_offset") = 0.0,
          py::arg("seed") = kDefaultArchiveSeed, py::arg("learning_rate") = py::none(),
          py::arg("threshold_min") = -std::numeric_limits<double>::infinity());
  bind_elite_archive<CvtArchive>(cvt);
  bind_thresholds<CvtArchive>(cvt);
  cvt.def_property_readonly("centroids", [](const ArchiveHandle<CvtArchive>& h) {
    const RowMatrix& c = h.archive.centroids();
    return rows_copy(c.data(), c.rows(), c.cols());
  });

  m.def(
      "cvt_centroids",
      [](Index dimensions, Index cells, Index samples, py::handle seed, std::optional<std::filesystem::path> cache_dir) {
        KMeansParams p;
        p.centroids = cells;
        p.samples = samples;
        p.init_samples = std::min(p.init_samples, samples);
        p.seed = seed_argument(seed);
        p.validate();
        const std::filesystem::path dir = cache_dir ? *cache_dir : default_centroid_cache_dir();
        CachedCentroids made;
        {
          const py::gil_scoped_release release;
          made = load_or_make_centroids(dimensions, p, dir);
        }
        return rows_copy(made.centroids.data(), made.centroids.rows(), made.centroids.cols());
      },
      py::arg("dimensions"), py::arg("cells") = 10'000, py::arg("samples") = 1'000'000, py::arg("seed") = 1,
      py::arg("cache_dir") = py::none(),
      "k-means centroids of uniform points in [0,1]^dimensions, as the CLI's [cvt] makes them (k-means++, Lloyd), "
      "from the centroid cache when there (cache_dir: default $XDG_CACHE_HOME/qdmeta/centroids; '' disables it)");

  using Unstructured = ArchiveHandle<UnstructuredArchive>;
  py::class_<Unstructured> unstructured(m, "UnstructuredArchive", R"doc(
AURORA's unstructured archive: elites at free points of the measure space; a candidate farther
than `threshold` from every member enters, a nearer one may take its nearest member's place
when it eps-dominates it on (objective, novelty). retrieve() gives the member nearest each
measure vector; `seed` seeds sample_elites().)doc");
  unstructured
      .def(py::init([](Index solution_dim, Index measure_dim, Index target_size, double eps, int novelty_neighbours,
                       double qd_offset, py::handle seed) {
             UnstructuredArchiveParams p;
             p.solution_size = solution_dim;
             p.measure_size = measure_dim;
             p.target_size = target_size;
             p.eps = eps;
             p.novelty_neighbours = novelty_neighbours;
             p.qd_offset = qd_offset;
             p.validate();
             return Unstructured(UnstructuredArchive(p), seed_argument(seed));
           }),
           py::arg("solution_dim"), py::arg("measure_dim"), py::arg("target_size") = 10'000, py::arg("eps") = 0.1,
           py::arg("novelty_neighbours") = 15, py::arg("qd_offset") = 0.0, py::arg("seed") = kDefaultArchiveSeed)
      .def(
          "add",
          [](Unstructured& h, py::handle s, py::handle o, py::handle mm, double threshold) {
            UnstructuredArchive& a = h.archive;
            if (!(threshold > 0)) throw py::value_error(fmt::format("threshold must be > 0, got {}", threshold));
            const AddArguments args(s, o, mm, py::none(), py::none(), a.params().solution_size,
                                    a.params().measure_size, 0);
            check_batch(args.batch(), 0, a.params().solution_size, a.params().measure_size, 0, "UnstructuredArchive");
            std::vector<AddStatus> status(static_cast<std::size_t>(args.rows));
            {
              const py::gil_scoped_release release;
              for (Index r = 0; r < args.rows; ++r)
                status[static_cast<std::size_t>(r)] =
                    a.add(args.solutions.data() + r * a.params().solution_size, args.objectives.data()[r],
                          args.measures.data() + r * a.params().measure_size, nullptr, threshold);
            }
            return statuses(status);
          },
          py::arg("solutions"), py::arg("objectives"), py::arg("measures"), py::arg("threshold"),
          "add(solutions, objectives, measures, threshold) -> statuses (0 rejected, 1 replaced a member, 2 added)")
      .def_property_readonly("stats", [](const Unstructured& h) { return h.archive.stats(); })
      .def_property_readonly("solution_dim", [](const Unstructured& h) { return h.archive.params().solution_size; })
      .def_property_readonly("measure_dim", [](const Unstructured& h) { return h.archive.params().measure_size; })
      .def("__len__", [](const Unstructured& h) { return h.archive.size(); })
      .def("clear", [](Unstructured& h) { h.archive.clear(); })
      .def("data", [](const Unstructured& h) { return elite_table_data(member_table(h.archive)); },
           "The members as numpy arrays: index (the slot), objective, measures, solution")
      .def("as_pandas", [](const Unstructured& h) { return elite_table_pandas(member_table(h.archive)); },
           "The members as a pandas DataFrame with pyribs's columns");
  bind_common<UnstructuredArchive>(unstructured, &member_table);
}

}  // namespace qdmeta::python
