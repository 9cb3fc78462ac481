#include "qdmeta/archive/unstructured_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

void UnstructuredArchiveParams::validate() const {
  require_range("aurora.latent_size", descriptor_size, Index{1}, Index{1'000});
  require_at_least("archive solution size", solution_size, Index{1});
  require_at_least("archive base-feature size", base_feature_size, Index{0});
  require_range("aurora.target_size", target_size, Index{1}, Index{100'000'000});
  require_range("aurora.eps", eps, 0.0, 0.999);
  require_range("aurora.novelty_neighbours", novelty_neighbours, 1, 1'000'000);
}

namespace {
double sign(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }
}  // namespace

bool eps_dominates(double candidate_fitness, double candidate_novelty, double member_fitness, double member_novelty,
                   double eps) {
  // The (1 - sign(s) eps) factor loosens the bound below s whatever the sign of s: for a
  // negative fitness such as Rastrigin's, (1 + eps) s is the lower value.
  return candidate_fitness >= (1.0 - sign(member_fitness) * eps) * member_fitness &&
         candidate_novelty >= (1.0 - sign(member_novelty) * eps) * member_novelty &&
         (candidate_fitness - member_fitness) * std::abs(member_novelty) >
             -(candidate_novelty - member_novelty) * std::abs(member_fitness);
}

namespace {
constexpr int kGridCells = 128;       // per grid axis
constexpr double kGridHalfWidth = 4;  // the grid spans [-4, 4] on each of its axes
constexpr double kCellSide = 2 * kGridHalfWidth / kGridCells;

int grid_coordinate(Real x) {
  const double c = std::floor((static_cast<double>(x) + kGridHalfWidth) / kCellSide);
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(kGridCells - 1)));
}
}  // namespace

UnstructuredArchive::UnstructuredArchive(UnstructuredArchiveParams params) : params_(params) {
  params_.validate();
  coordinates_.resize(static_cast<std::size_t>(params_.descriptor_size));
  grid_dims_ = std::min<Index>(params_.descriptor_size, 2);
  cells_.resize(static_cast<std::size_t>(grid_dims_ > 1 ? kGridCells * kGridCells : kGridCells));
}


std::int32_t UnstructuredArchive::cell_of(const Real* point, std::int32_t* column_row) const {
  const int cx = grid_coordinate(point[0]);
  const int cy = grid_dims_ > 1 ? grid_coordinate(point[1]) : 0;
  if (column_row) {
    column_row[0] = cx;
    column_row[1] = cy;
  }
  return cx * (grid_dims_ > 1 ? kGridCells : 1) + cy;
}

void UnstructuredArchive::index_insert(Index slot) {
  Real point[2] = {coordinates_[0][static_cast<std::size_t>(slot)], 0.0f};
  if (grid_dims_ > 1) point[1] = coordinates_[1][static_cast<std::size_t>(slot)];
  const std::int32_t cell = cell_of(point);
  cells_[static_cast<std::size_t>(cell)].push_back(slot);
  if (static_cast<std::size_t>(slot) >= cell_of_slot_.size()) cell_of_slot_.resize(static_cast<std::size_t>(slot) + 1);
  cell_of_slot_[static_cast<std::size_t>(slot)] = cell;
}

void UnstructuredArchive::index_erase(Index slot) {
  auto& members = cells_[static_cast<std::size_t>(cell_of_slot_[static_cast<std::size_t>(slot)])];
  const auto it = std::find(members.begin(), members.end(), slot);
  *it = members.back();  // order inside a cell does not matter: ties go by slot
  members.pop_back();
}

std::vector<UnstructuredArchive::Neighbour> UnstructuredArchive::nearest(const Real* point, Index count,
                                                                         Index excluded) const {
  std::vector<Neighbour> best;
  if (count <= 0 || empty()) return best;
  const auto m = static_cast<std::size_t>(count);
  best.reserve(m + 1);
  const Index d = params_.descriptor_size;
  Real worst = std::numeric_limits<Real>::infinity();  // the m-th best squared distance so far
  const int rows = grid_dims_ > 1 ? kGridCells : 1;
  const auto visit_cell = [&](int cx, int cy) {
    for (const Index slot : cells_[static_cast<std::size_t>(cx * rows + cy)]) {
      Real d2 = 0.0f;
      for (Index j = 0; j < d; ++j) {
        const Real diff = coordinates_[static_cast<std::size_t>(j)][static_cast<std::size_t>(slot)] - point[j];
        d2 += diff * diff;
      }
      if (d2 > worst || slot == excluded) continue;
      const Neighbour candidate{d2, slot};
      if (best.size() == m && !(candidate < best.back())) continue;
      best.insert(std::upper_bound(best.begin(), best.end(), candidate), candidate);
      if (best.size() > m) best.pop_back();
      if (best.size() == m) worst = best.back().squared_distance;
    }
  };
  std::int32_t q[2];
  cell_of(point, q);
  for (int r = 0; r < kGridCells; ++r) {
    // A member in ring r is at least (r - 1) cell sides away along one grid axis (clamped
    // members lie farther out than their cell); the margin absorbs rounding in the cell index.
    const double bound = std::max(0.0, (r - 1) * kCellSide - 1e-3 * kCellSide);
    if (best.size() == m && bound * bound > static_cast<double>(worst)) break;
    const int x0 = q[0] - r, x1 = q[0] + r, y0 = q[1] - r, y1 = q[1] + r;
    for (int cx = std::max(x0, 0); cx <= std::min(x1, kGridCells - 1); ++cx) {
      if (cx == x0 || cx == x1) {  // a full column of the ring
        for (int cy = std::max(y0, 0); cy <= std::min(y1, rows - 1); ++cy) visit_cell(cx, cy);
      } else {  // only the top and bottom cells
        if (y0 >= 0) visit_cell(cx, y0);
        if (y1 < rows && y1 != y0) visit_cell(cx, y1);
      }
    }
  }
  return best;
}

double UnstructuredArchive::member_novelty(Index slot) const {
  std::vector<Real> point(coordinates_.size());
  for (std::size_t j = 0; j < coordinates_.size(); ++j) point[j] = coordinates_[j][static_cast<std::size_t>(slot)];
  const std::vector<Neighbour> nn = nearest(point.data(), params_.novelty_neighbours, slot);
  if (nn.empty()) return 0.0;
  double sum = 0.0;
  for (const Neighbour& x : nn) sum += std::sqrt(static_cast<double>(x.squared_distance));
  return sum / static_cast<double>(nn.size());
}

AddStatus UnstructuredArchive::add(const Real* solution, Real objective, const Real* descriptor,
                                   const Real* base_features, double threshold) {
  for (Index j = 0; j < params_.descriptor_size; ++j)
    if (!std::isfinite(descriptor[j])) throw Error(fmt::format("unstructured archive: descriptor {} is not finite", j));
  if (empty()) {
    append(solution, objective, descriptor, base_features);
    return AddStatus::kNew;
  }
  // The k + 1 nearest: the nearest, then the k that give the candidate's novelty without it.
  const std::vector<Neighbour> nn = nearest(descriptor, params_.novelty_neighbours + 1);
  if (std::sqrt(static_cast<double>(nn[0].squared_distance)) > threshold) {
    append(solution, objective, descriptor, base_features);
    return AddStatus::kNew;
  }
  if (nn.size() == 1) return AddStatus::kNotAdded;
  if (std::sqrt(static_cast<double>(nn[1].squared_distance)) < (1.0 - params_.eps) * threshold)
    return AddStatus::kNotAdded;
  double candidate_novelty = 0.0;
  for (std::size_t i = 1; i < nn.size(); ++i) candidate_novelty += std::sqrt(static_cast<double>(nn[i].squared_distance));
  candidate_novelty /= static_cast<double>(nn.size() - 1);
  const Index slot = nn[0].slot;
  if (!eps_dominates(objective, candidate_novelty, objectives_[static_cast<std::size_t>(slot)], member_novelty(slot),
                     params_.eps))
    return AddStatus::kNotAdded;
  overwrite(slot, solution, objective, descriptor, base_features);
  return AddStatus::kImproved;
}

void UnstructuredArchive::append(const Real* solution, Real objective, const Real* descriptor,
                                 const Real* base_features) {
  const Index slot = size();
  objectives_.push_back(objective);
  solutions_.insert(solutions_.end(), solution, solution + params_.solution_size);
  if (params_.base_feature_size > 0) {
    if (base_features) base_.insert(base_.end(), base_features, base_features + params_.base_feature_size);
    else base_.resize(base_.size() + static_cast<std::size_t>(params_.base_feature_size), 0.0f);
  }
  for (std::size_t j = 0; j < coordinates_.size(); ++j) coordinates_[j].push_back(descriptor[j]);
  index_insert(slot);
}

void UnstructuredArchive::overwrite(Index slot, const Real* solution, Real objective, const Real* descriptor,
                                    const Real* base_features) {
  index_erase(slot);
  objectives_[static_cast<std::size_t>(slot)] = objective;
  std::copy_n(solution, params_.solution_size, solutions_.begin() + slot * params_.solution_size);
  if (params_.base_feature_size > 0 && base_features)
    std::copy_n(base_features, params_.base_feature_size, base_.begin() + slot * params_.base_feature_size);
  for (std::size_t j = 0; j < coordinates_.size(); ++j) coordinates_[j][static_cast<std::size_t>(slot)] = descriptor[j];
  index_insert(slot);
}

void UnstructuredArchive::clear() {
  objectives_.clear();
  solutions_.clear();
  base_.clear();
  for (auto& c : coordinates_) c.clear();
  for (auto& c : cells_) c.clear();
  cell_of_slot_.clear();
}

ArchiveStats UnstructuredArchive::stats() const {
  // Coverage is not a fraction of cells (there are none) but of the size the container is
  // steered toward, capped at 1.
  return archive_stats(
      [&](auto&& visit) {
        for (Real f : objectives_) visit(static_cast<double>(f));
      },
      static_cast<double>(params_.target_size), params_.qd_offset);
}

void UnstructuredArchive::save(BinaryWriter& out) const {
  out.tag("unstructured_archive");
  out.value<std::int64_t>(params_.descriptor_size);
  out.value<std::int64_t>(params_.solution_size);
  out.value<std::int64_t>(params_.base_feature_size);
  out.values(objectives_);
  out.values(solutions_);
  out.values(base_);
  for (const auto& c : coordinates_) out.values(c);
}

void UnstructuredArchive::load(BinaryReader& in) {
  in.expect_tag("unstructured_archive");
  const auto dims = in.value<std::int64_t>("archive descriptor size");
  const auto genes = in.value<std::int64_t>("archive solution size");
  const auto base = in.value<std::int64_t>("archive base-feature size");
  if (dims != params_.descriptor_size || genes != params_.solution_size || base != params_.base_feature_size)
    in.fail("unstructured archive of another shape than this run's");
  const auto objectives = in.values<Real>("archive objectives");
  const auto solutions = in.values<Real>("archive solutions");
  const auto base_features = in.values<Real>("archive base features");
  std::vector<std::vector<Real>> coordinates;
  for (Index j = 0; j < dims; ++j) coordinates.push_back(in.values<Real>("archive descriptors"));
  const std::size_t n = objectives.size();
  bool consistent = solutions.size() == n * static_cast<std::size_t>(genes) &&
                    base_features.size() == n * static_cast<std::size_t>(base);
  for (const auto& c : coordinates) consistent = consistent && c.size() == n;
  if (!consistent) in.fail("unstructured archive contents disagree in size");
  clear();
  std::vector<Real> descriptor(static_cast<std::size_t>(dims));
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < descriptor.size(); ++j) descriptor[j] = coordinates[j][i];
    append(solutions.data() + i * static_cast<std::size_t>(genes), objectives[i], descriptor.data(),
           base > 0 ? base_features.data() + i * static_cast<std::size_t>(base) : nullptr);
  }
}

}  // namespace qdmeta
