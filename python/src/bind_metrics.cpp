// Measures of an archive beyond its statistics: the CQD score's kernel (python/qdmeta/_cqd.py is
// the pyribs-named function around it).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <span>
#include <vector>

#include "bindings.hpp"
#include "double_arrays.hpp"
#include "qdmeta/archive/cqd_score.hpp"

namespace py = pybind11;

namespace qdmeta::python {
void bind_metrics(py::module_& m) {
  m.def(
      "_cqd_score",
      [](const DoubleArray& objectives, const DoubleArray& measures, std::size_t measure_dim,
         const DoubleArray& target_points, std::size_t iterations, const DoubleArray& penalties, double obj_min,
         double obj_max, double dist_max, double dist_ord) {
        CqdSettings settings;
        settings.penalties.assign(penalties.data(), penalties.data() + penalties.size());
        settings.obj_min = obj_min;
        settings.obj_max = obj_max;
        settings.dist_max = dist_max;
        settings.dist_ord = dist_ord;
        CqdScore score;
        {
          py::gil_scoped_release free;
          score = cqd_score(values(objectives), values(measures), measure_dim, values(target_points), iterations,
                            settings);
        }
        auto scores = new_array<double>({static_cast<py::ssize_t>(score.scores.size())});
        std::copy(score.scores.begin(), score.scores.end(), scores.mutable_data());
        return py::make_tuple(scores, score.mean);
      },
      "The CQD score's kernel (qdmeta.cqd_score is the function to call): (scores per iteration, mean).");
  m.def("_evenly_spaced_penalties", &evenly_spaced_penalties, "count penalties from 0 to 1, evenly spaced");
}

}  // namespace qdmeta::python
