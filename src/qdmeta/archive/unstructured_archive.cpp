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

UnstructuredArchive::UnstructuredArchive(UnstructuredArchiveParams params) : params_(params) {
  params_.validate();
  coordinates_.resize(static_cast<std::size_t>(params_.descriptor_size));
}

void UnstructuredArchive::scan(const Real* point) const {
  const std::size_t n = objectives_.size();
  distances_.assign(n, 0.0f);
  Real* d = distances_.data();
  for (std::size_t j = 0; j < coordinates_.size(); ++j) {
    const Real* c = coordinates_[j].data();
    const Real q = point[j];
    for (std::size_t i = 0; i < n; ++i) {
      const Real diff = c[i] - q;
      d[i] += diff * diff;
    }
  }
}

double UnstructuredArchive::mean_nearest(Index excluded) const {
  selection_.clear();
  for (std::size_t i = 0; i < distances_.size(); ++i)
    if (static_cast<Index>(i) != excluded) selection_.push_back(distances_[i]);
  const std::size_t k = std::min(selection_.size(), static_cast<std::size_t>(params_.novelty_neighbours));
  if (k == 0) return 0.0;
  std::nth_element(selection_.begin(), selection_.begin() + static_cast<std::ptrdiff_t>(k - 1), selection_.end());
  double sum = 0.0;  // the k smallest are now in front, in some order: summed in sorted order
  std::sort(selection_.begin(), selection_.begin() + static_cast<std::ptrdiff_t>(k));
  for (std::size_t i = 0; i < k; ++i) sum += std::sqrt(static_cast<double>(selection_[i]));
  return sum / static_cast<double>(k);
}

double UnstructuredArchive::member_novelty(Index slot) const {
  std::vector<Real> point(coordinates_.size());
  for (std::size_t j = 0; j < coordinates_.size(); ++j) point[j] = coordinates_[j][static_cast<std::size_t>(slot)];
  scan(point.data());
  return mean_nearest(slot);
}

AddStatus UnstructuredArchive::add(const Real* solution, Real objective, const Real* descriptor,
                                   const Real* base_features, double threshold) {
  for (Index j = 0; j < params_.descriptor_size; ++j)
    if (!std::isfinite(descriptor[j])) throw Error(fmt::format("unstructured archive: descriptor {} is not finite", j));
  if (empty()) {
    append(solution, objective, descriptor, base_features);
    return AddStatus::kNew;
  }
  scan(descriptor);
  // Nearest and second nearest; ties go to the lower slot.
  constexpr Real kInf = std::numeric_limits<Real>::infinity();
  Real d1 = kInf, d2 = kInf;
  Index nearest = 0;
  for (std::size_t i = 0; i < distances_.size(); ++i) {
    const Real d = distances_[i];
    if (d < d2) {
      if (d < d1) {
        d2 = d1;
        d1 = d;
        nearest = static_cast<Index>(i);
      } else {
        d2 = d;
      }
    }
  }
  if (std::sqrt(static_cast<double>(d1)) > threshold) {
    append(solution, objective, descriptor, base_features);
    return AddStatus::kNew;
  }
  if (size() == 1) return AddStatus::kNotAdded;
  if (std::sqrt(static_cast<double>(d2)) < (1.0 - params_.eps) * threshold) return AddStatus::kNotAdded;
  const double candidate_novelty = mean_nearest(nearest);
  const double member_novelty_value = member_novelty(nearest);
  if (!eps_dominates(objective, candidate_novelty, objectives_[static_cast<std::size_t>(nearest)],
                     member_novelty_value, params_.eps))
    return AddStatus::kNotAdded;
  overwrite(nearest, solution, objective, descriptor, base_features);
  return AddStatus::kImproved;
}

void UnstructuredArchive::append(const Real* solution, Real objective, const Real* descriptor,
                                 const Real* base_features) {
  objectives_.push_back(objective);
  solutions_.insert(solutions_.end(), solution, solution + params_.solution_size);
  if (params_.base_feature_size > 0) {
    if (base_features) base_.insert(base_.end(), base_features, base_features + params_.base_feature_size);
    else base_.resize(base_.size() + static_cast<std::size_t>(params_.base_feature_size), 0.0f);
  }
  for (std::size_t j = 0; j < coordinates_.size(); ++j) coordinates_[j].push_back(descriptor[j]);
}

void UnstructuredArchive::overwrite(Index slot, const Real* solution, Real objective, const Real* descriptor,
                                    const Real* base_features) {
  objectives_[static_cast<std::size_t>(slot)] = objective;
  std::copy_n(solution, params_.solution_size, solutions_.begin() + slot * params_.solution_size);
  if (params_.base_feature_size > 0 && base_features)
    std::copy_n(base_features, params_.base_feature_size, base_.begin() + slot * params_.base_feature_size);
  for (std::size_t j = 0; j < coordinates_.size(); ++j) coordinates_[j][static_cast<std::size_t>(slot)] = descriptor[j];
}

void UnstructuredArchive::clear() {
  objectives_.clear();
  solutions_.clear();
  base_.clear();
  for (auto& c : coordinates_) c.clear();
}

ArchiveStats UnstructuredArchive::stats() const {
  ArchiveStats s;
  s.num_elites = size();
  // Not a fraction of cells (there are none): of the size the container is steered toward.
  s.coverage = std::min(1.0, static_cast<double>(s.num_elites) / static_cast<double>(params_.target_size));
  if (empty()) return s;
  double sum = 0.0;
  double best = -std::numeric_limits<double>::infinity();
  for (Real f : objectives_) {
    sum += f;
    best = std::max(best, static_cast<double>(f));
  }
  s.obj_max = best;
  s.obj_mean = sum / static_cast<double>(s.num_elites);
  s.qd_score = sum - params_.qd_offset * static_cast<double>(s.num_elites);
  s.norm_qd_score = s.qd_score / static_cast<double>(params_.target_size);
  return s;
}

}  // namespace qdmeta
