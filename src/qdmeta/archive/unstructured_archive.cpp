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
  sorted_coordinates_.resize(static_cast<std::size_t>(params_.descriptor_size));
}

std::size_t UnstructuredArchive::sorted_position(Real key, Index slot) const {
  const std::vector<Real>& keys = sorted_coordinates_[0];
  std::size_t lo = 0, hi = sorted_slots_.size();
  while (lo < hi) {  // first entry not before (key, slot)
    const std::size_t mid = (lo + hi) / 2;
    const Real k = keys[mid];
    if (k < key || (k == key && sorted_slots_[mid] < slot)) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

void UnstructuredArchive::index_insert(Index slot) {
  const auto s = static_cast<std::size_t>(slot);
  const auto pos = static_cast<std::ptrdiff_t>(sorted_position(coordinates_[0][s], slot));
  sorted_slots_.insert(sorted_slots_.begin() + pos, slot);
  for (std::size_t j = 0; j < coordinates_.size(); ++j)
    sorted_coordinates_[j].insert(sorted_coordinates_[j].begin() + pos, coordinates_[j][s]);
}

void UnstructuredArchive::index_erase(Index slot) {
  const auto pos =
      static_cast<std::ptrdiff_t>(sorted_position(coordinates_[0][static_cast<std::size_t>(slot)], slot));
  sorted_slots_.erase(sorted_slots_.begin() + pos);
  for (auto& c : sorted_coordinates_) c.erase(c.begin() + pos);
}

namespace {

using Neighbour = UnstructuredArchive::Neighbour;

// The sweep of UnstructuredArchive::nearest over `n` members sorted by their first coordinate
// (coords[j][pos]). kDims > 0 fixes the dimension at compile time for the common latent sizes;
// 0 reads `dims`. Squared distances are summed from the first coordinate on, exactly as a
// plain loop would, so a gap term alone is never above the full distance.
template <int kDims>
void sweep(const Real* const* coords, Index dims, const Index* slots, std::size_t n, const Real* point,
           std::size_t m, Index excluded, std::vector<Neighbour>& best) {
  const Index d = kDims > 0 ? kDims : dims;
  const Real* keys = coords[0];
  const Real q0 = point[0];
  const std::size_t start = static_cast<std::size_t>(std::lower_bound(keys, keys + n, q0) - keys);
  Real worst = std::numeric_limits<Real>::infinity();  // the m-th best squared distance so far
  // The rare path: a member at least as near as the worst kept one.
  const auto consider = [&](std::size_t pos, Real d2) {
    const Index slot = slots[pos];
    if (slot == excluded) return;
    const Neighbour candidate{d2, slot};
    if (best.size() == m && !(candidate < best.back())) return;
    best.insert(std::upper_bound(best.begin(), best.end(), candidate), candidate);
    if (best.size() > m) best.pop_back();
    if (best.size() == m) worst = best.back().squared_distance;
  };
  // The hot path, kept inline in each loop: the squared distance from the gap term on.
  const auto distance2 = [&](std::size_t pos, Real gap) {
    Real d2 = gap * gap;
    for (Index j = 1; j < d; ++j) {
      const Real diff = coords[j][pos] - point[j];
      d2 += diff * diff;
    }
    return d2;
  };
  // Seed with the m + 1 entries on each side of the query's position, then sweep right and
  // left until the gap along the first coordinate alone exceeds the worst kept distance.
  const std::size_t seed_lo = start > m + 1 ? start - (m + 1) : 0;
  const std::size_t seed_hi = std::min(n, start + m + 1);
  for (std::size_t pos = seed_lo; pos < seed_hi; ++pos) consider(pos, distance2(pos, keys[pos] - q0));
  for (std::size_t pos = seed_hi; pos < n; ++pos) {
    const Real gap = keys[pos] - q0;
    if (gap * gap > worst) break;
    const Real d2 = distance2(pos, gap);
    if (d2 <= worst) consider(pos, d2);
  }
  for (std::size_t pos = seed_lo; pos-- > 0;) {
    const Real gap = keys[pos] - q0;
    if (gap * gap > worst) break;
    const Real d2 = distance2(pos, gap);
    if (d2 <= worst) consider(pos, d2);
  }
}

}  // namespace

std::vector<UnstructuredArchive::Neighbour> UnstructuredArchive::nearest(const Real* point, Index count,
                                                                         Index excluded) const {
  std::vector<Neighbour> best;
  if (count <= 0 || empty()) return best;
  const auto m = static_cast<std::size_t>(count);
  best.reserve(m + 1);
  std::vector<const Real*> coords;
  for (const auto& c : sorted_coordinates_) coords.push_back(c.data());
  const Index d = params_.descriptor_size;
  const std::size_t n = sorted_slots_.size();
  switch (d) {
    case 1: sweep<1>(coords.data(), d, sorted_slots_.data(), n, point, m, excluded, best); break;
    case 2: sweep<2>(coords.data(), d, sorted_slots_.data(), n, point, m, excluded, best); break;
    case 3: sweep<3>(coords.data(), d, sorted_slots_.data(), n, point, m, excluded, best); break;
    case 4: sweep<4>(coords.data(), d, sorted_slots_.data(), n, point, m, excluded, best); break;
    default: sweep<0>(coords.data(), d, sorted_slots_.data(), n, point, m, excluded, best); break;
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
  for (auto& c : sorted_coordinates_) c.clear();
  sorted_slots_.clear();
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
