#include "archive_queries.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "elite_arrays.hpp"
#include "numpy_arrays.hpp"
#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// The three archives behind one set of accessors: sizes, the member holding the elite for a
// measure vector, the k-th member and the copy of one member into a table row.
struct Sizes {
  Index solution = 0, measures = 0, base = 0;
};

Sizes sizes_of(const GridArchive& a) { return {a.solution_size(), a.dimensions(), a.base_feature_size()}; }
Sizes sizes_of(const CvtArchive& a) { return {a.solution_size(), a.dimensions(), 0}; }
Sizes sizes_of(const UnstructuredArchive& a) {
  return {a.params().solution_size, a.params().measure_size, a.params().base_feature_size};
}

// The cell whose elite a measure vector retrieves, -1 when that cell is empty.
template <class CellArchive>
Index elite_at(const CellArchive& a, const Real* measures) {
  const Index cell = a.index_of(measures);
  return a.occupied(cell) ? cell : -1;
}
Index elite_at(const UnstructuredArchive& a, const Real* measures) {
  return a.empty() ? -1 : a.nearest(measures, 1).front().slot;
}

// The k-th member, k in [0, size): cells in fill order (the order sample_cell draws from).
template <class CellArchive>
Index member(const CellArchive& a, Index k) {
  return a.filled_cells()[static_cast<std::size_t>(k)];
}
Index member(const UnstructuredArchive&, Index k) { return k; }

template <class CellArchive>
void copy_elite(const CellArchive& a, Index cell, const Sizes& n, EliteTable& t, Index row) {
  t.objective[static_cast<std::size_t>(row)] = a.objective(cell);
  std::copy_n(a.solution(cell), n.solution, t.solutions.row(row).data());
  std::copy_n(a.measures(cell), n.measures, t.measures.row(row).data());
  if constexpr (requires { a.base_features(cell); })
    if (n.base > 0) std::copy_n(a.base_features(cell), n.base, t.base_features.row(row).data());
}
void copy_elite(const UnstructuredArchive& a, Index slot, const Sizes& n, EliteTable& t, Index row) {
  t.objective[static_cast<std::size_t>(row)] = a.objective(slot);
  std::copy_n(a.solution(slot), n.solution, t.solutions.row(row).data());
  for (Index k = 0; k < n.measures; ++k) t.measures(row, k) = a.descriptor(slot, k);
  if (n.base > 0) std::copy_n(a.base_features(slot), n.base, t.base_features.row(row).data());
}

// The elites of `cells` (-1: none, a row of NaN with index -1), one table row each.
template <class Archive>
EliteTable elites_of(const Archive& a, const std::vector<Index>& cells) {
  const Sizes n = sizes_of(a);
  const auto rows = static_cast<Index>(cells.size());
  constexpr Real nan = std::numeric_limits<Real>::quiet_NaN();
  EliteTable t;
  t.index.assign(cells.begin(), cells.end());
  t.objective.assign(cells.size(), nan);
  t.solutions.setConstant(rows, n.solution, nan);
  t.measures.setConstant(rows, n.measures, nan);
  t.base_features.setConstant(rows, n.base, nan);
  for (Index r = 0; r < rows; ++r)
    if (cells[static_cast<std::size_t>(r)] >= 0) copy_elite(a, cells[static_cast<std::size_t>(r)], n, t, r);
  return t;
}

std::vector<Index> cells_at(const auto& a, const FloatArray& m, Index dimensions) {
  std::vector<Index> cells(static_cast<std::size_t>(m.shape(0)));
  for (py::ssize_t i = 0; i < m.shape(0); ++i) cells[static_cast<std::size_t>(i)] = elite_at(a, m.data() + i * dimensions);
  return cells;
}

py::array_t<bool> occupied_flags(const std::vector<Index>& cells) {
  py::array_t<bool> out = new_array<bool>({static_cast<py::ssize_t>(cells.size())});
  for (std::size_t i = 0; i < cells.size(); ++i) out.mutable_data()[i] = cells[i] >= 0;
  return out;
}

// Row r of an elite-table dict as one elite: scalars for index and objective, arrays for the rest.
py::dict elite_row(const py::dict& data, py::ssize_t r) {
  py::dict elite;
  for (const auto& [name, column] : data) {
    const py::array a = py::reinterpret_borrow<py::array>(column);
    py::object v = a[py::int_(r)];
    if (a.ndim() == 1) v = v.attr("item")();  // a Python int or float
    elite[name] = v;
  }
  return elite;
}

// A snapshot of an archive's elites, handed out one dict at a time.
class EliteIterator {
 public:
  explicit EliteIterator(EliteTable table) : data_(elite_table_data(table)), size_(table.size()) {}
  py::dict next() {
    if (next_ >= size_) throw py::stop_iteration();
    return elite_row(data_, next_++);
  }
  Index remaining() const { return size_ - next_; }

 private:
  py::dict data_;
  Index size_;
  Index next_ = 0;
};

}  // namespace

FloatArray measure_rows(py::handle measures, Index rows, Index dimensions) {
  FloatArray m = float_rows(measures, rows, dimensions, "measures");
  for (py::ssize_t i = 0; i < m.shape(0); ++i)
    for (Index k = 0; k < dimensions; ++k)
      if (!std::isfinite(m.data()[i * dimensions + k]))
        throw InputError(fmt::format("measures row {} column {} is {}, not a finite number", i, k,
                                     m.data()[i * dimensions + k]));
  return m;
}

template <class Archive>
py::tuple retrieve(const Archive& a, py::handle measures) {
  const Index d = sizes_of(a).measures;
  const std::vector<Index> cells = cells_at(a, measure_rows(measures, -1, d), d);
  return py::make_tuple(occupied_flags(cells), elite_table_data(elites_of(a, cells)));
}

template <class Archive>
py::tuple retrieve_single(const Archive& a, py::handle measures) {
  const Index d = sizes_of(a).measures;
  FloatArray m = float_rows(measures, d, -1, "measures");
  const py::tuple batch = retrieve(a, m.reshape({py::ssize_t{1}, static_cast<py::ssize_t>(d)}));
  const py::array_t<bool> occupied = batch[0].cast<py::array_t<bool>>();
  return py::make_tuple(occupied.data()[0], elite_row(batch[1].cast<py::dict>(), 0));
}

template <class Archive>
py::dict sample_elites(const Archive& a, Rng rng, Index n, bool replace) {
  const Index size = static_cast<Index>(a.size());
  if (n < 0) throw InputError(fmt::format("sample_elites(): n must be >= 0, got {}", n));
  if (size == 0) throw InputError("sample_elites(): the archive is empty");
  if (!replace && n > size)
    throw InputError(fmt::format("sample_elites(): n = {} is more than the archive's {} elites, without replacement "
                                 "(replace=False)",
                                 n, size));
  std::vector<Index> cells(static_cast<std::size_t>(n));
  if (replace) {
    for (Index& c : cells) c = member(a, static_cast<Index>(rng.below(static_cast<std::uint64_t>(size))));
  } else {
    std::vector<Index> order(static_cast<std::size_t>(size));
    std::iota(order.begin(), order.end(), Index{0});
    choose_without_replacement(order, static_cast<std::size_t>(n), rng);
    for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = member(a, order[i]);
  }
  return elite_table_data(elites_of(a, cells));
}

EliteTable member_table(const UnstructuredArchive& a) {
  std::vector<Index> slots(static_cast<std::size_t>(a.size()));
  std::iota(slots.begin(), slots.end(), Index{0});
  return elites_of(a, slots);
}

py::object iterate_elites(EliteTable table) { return py::cast(EliteIterator(std::move(table))); }

void bind_elite_iterator(py::module_& m) {
  py::class_<EliteIterator>(m, "EliteIterator", "Iterates over a snapshot of an archive's elites, one dict each")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &EliteIterator::next)
      .def("__length_hint__", &EliteIterator::remaining);
}

template py::tuple retrieve(const GridArchive&, py::handle);
template py::tuple retrieve(const CvtArchive&, py::handle);
template py::tuple retrieve(const UnstructuredArchive&, py::handle);
template py::tuple retrieve_single(const GridArchive&, py::handle);
template py::tuple retrieve_single(const CvtArchive&, py::handle);
template py::tuple retrieve_single(const UnstructuredArchive&, py::handle);
template py::dict sample_elites(const GridArchive&, Rng, Index, bool);
template py::dict sample_elites(const CvtArchive&, Rng, Index, bool);
template py::dict sample_elites(const UnstructuredArchive&, Rng, Index, bool);

}  // namespace qdmeta::python
