#include "qdmeta/archive/unstructured_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

void UnstructuredArchiveParams::validate() const {
  require_range("aurora.latent_size", measure_size, Index{1}, Index{1'000});
  require_at_least("archive solution size", solution_size, Index{1});
  require_at_least("archive base-feature size", base_feature_size, Index{0});
  require(kTargetSize, target_size);
  require(kEps, eps);
  require(kNoveltyNeighbours, novelty_neighbours);
}

namespace {
double sign(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }
}  // namespace

bool eps_fitness_allows(double candidate_fitness, double member_fitness, double eps) {
  // The (1 - sign(s) eps) factor loosens the bound below s whatever the sign of s: for a
  // negative fitness such as Rastrigin's, (1 + eps) s is the lower value.
  return candidate_fitness >= (1.0 - sign(member_fitness) * eps) * member_fitness;
}

bool eps_dominates(double candidate_fitness, double candidate_novelty, double member_fitness, double member_novelty,
                   double eps) {
  return eps_fitness_allows(candidate_fitness, member_fitness, eps) &&
         candidate_novelty >= (1.0 - sign(member_novelty) * eps) * member_novelty &&
         (candidate_fitness - member_fitness) * std::abs(member_novelty) >
             -(candidate_novelty - member_novelty) * std::abs(member_fitness);
}

namespace {
const UnstructuredArchiveParams& checked(const UnstructuredArchiveParams& p) {
  p.validate();
  return p;
}
}  // namespace

UnstructuredArchive::UnstructuredArchive(UnstructuredArchiveParams params)
    : params_(checked(params)), grid_(params_.measure_size) {
  coordinates_.resize(static_cast<std::size_t>(params_.measure_size));
  member_.resize(static_cast<std::size_t>(params_.measure_size));
}

std::vector<UnstructuredArchive::Neighbour> UnstructuredArchive::nearest(const Real* point, Index count,
                                                                         Index excluded) const {
  std::vector<Neighbour> best;
  grid_.nearest(point, count, excluded, best);
  return best;
}

double UnstructuredArchive::member_novelty(Index slot) const {
  std::vector<Real> point(coordinates_.size());
  for (std::size_t j = 0; j < coordinates_.size(); ++j) point[j] = coordinates_[j][static_cast<std::size_t>(slot)];
  std::vector<Neighbour> nn;
  grid_.nearest(point.data(), params_.novelty_neighbours, slot, nn);
  if (nn.empty()) return 0.0;
  double sum = 0.0;
  for (const Neighbour& x : nn) sum += std::sqrt(static_cast<double>(x.squared_distance));
  return sum / static_cast<double>(nn.size());
}

void UnstructuredArchive::check_finite(const Real* descriptor) const {
  for (Index j = 0; j < params_.measure_size; ++j)
    if (!std::isfinite(descriptor[j])) throw Error(fmt::format("unstructured archive: descriptor {} is not finite", j));
}

AddStatus UnstructuredArchive::add(const Real* solution, Real objective, const Real* descriptor,
                                   const Real* base_features, double threshold, Index* slot) {
  check_finite(descriptor);
  if (empty()) {
    if (slot) *slot = size();
    append(solution, objective, descriptor, base_features);
    return AddStatus::kNew;
  }
  return add_near(solution, objective, descriptor, base_features, threshold, slot);
}

AddStatus UnstructuredArchive::add_near(const Real* solution, Real objective, const Real* descriptor,
                                        const Real* base_features, double threshold, Index* written) {
  if (written) *written = -1;
  // One pass over rings of grid cells around the candidate answers every question of the rule
  // in turn, each as soon as the points seen so far decide it. The answers are those of exact
  // queries (PointGrid::nearest): a distance counts only once the rings reach past it.
  constexpr double kEverywhere = std::numeric_limits<double>::infinity();
  const auto k = static_cast<std::size_t>(params_.novelty_neighbours);
  const double crowded = (1.0 - params_.eps) * threshold;
  spans_.clear();
  near_.reset(k + 1);  // the candidate's k + 1 nearest among the points seen, nearest first
  for (int r = 0;; ++r) {
    const std::size_t before = spans_.size();
    const double reach = grid_.ring_spans(descriptor, r, spans_);
    for (std::size_t i = before; i < spans_.size(); ++i) grid_.offer(spans_[i], descriptor, -1, near_);
    // Added when the nearest member is farther than l (reach is +infinity once all is seen).
    if (!(near_.size() > 0 && near_.distance(0) <= threshold) && reach > threshold) {
      if (written) *written = size();
      append(solution, objective, descriptor, base_features);
      return AddStatus::kNew;
    }
    // Rejected when the second nearest is nearer than (1 - eps) l, or there is none.
    if (near_.size() >= 2 && near_.distance(1) < crowded) return AddStatus::kNotAdded;
    if (reach != kEverywhere && !(near_.size() >= 2 && near_.distance(1) < reach)) continue;
    if (near_.size() == 1) return AddStatus::kNotAdded;
    // Otherwise the nearest member is replaced when the candidate eps-dominates it on (fitness,
    // novelty); fitness alone can refuse.
    const Index slot = key_slot(near_[0]);
    const double member_fitness = objectives_[static_cast<std::size_t>(slot)];
    if (!eps_fitness_allows(objective, member_fitness, params_.eps)) return AddStatus::kNotAdded;
    if (reach != kEverywhere && !(near_.full() && near_.distance(k) < reach)) continue;
    const double farthest = near_.full() ? near_.distance(k) : kEverywhere;
    if (!member_neighbours(slot, near_.distance(0), farthest, reach)) continue;
    double candidate_novelty = 0.0, member_novelty = 0.0;
    for (std::size_t i = 1; i < near_.size(); ++i) candidate_novelty += near_.distance(i);
    candidate_novelty /= static_cast<double>(near_.size() - 1);
    for (std::size_t i = 0; i < around_.size(); ++i) member_novelty += around_.distance(i);
    if (around_.size() > 0) member_novelty /= static_cast<double>(around_.size());
    if (!eps_dominates(objective, candidate_novelty, member_fitness, member_novelty, params_.eps))
      return AddStatus::kNotAdded;
    overwrite(slot, solution, objective, descriptor, base_features);
    if (written) *written = slot;
    return AddStatus::kImproved;
  }
}

bool UnstructuredArchive::member_neighbours(Index slot, double nearest, double farthest, double reach) {
  // The member's k nearest others among the points seen around the candidate, which hold every
  // member within `reach` of the candidate: exact once `nearest` (candidate to member) plus
  // the member's k-th is within reach (triangle inequality). The candidate's k nearest others
  // (within `farthest` of it) lie within nearest + farthest of the member, which bounds its
  // k-th from the start (1e-5 spares float rounding).
  const Index d = params_.measure_size;
  const auto k = static_cast<std::size_t>(params_.novelty_neighbours);
  Real* m = member_.data();
  for (Index j = 0; j < d; ++j) m[j] = coordinates_[static_cast<std::size_t>(j)][static_cast<std::size_t>(slot)];
  const double ceiling = (nearest + farthest) * (1.0 + 1e-5);
  around_.reset(k, std::nextafter(static_cast<Real>(ceiling * ceiling), std::numeric_limits<Real>::infinity()));
  for (const PointGrid::Span& span : spans_) grid_.offer(span, m, slot, around_);
  return reach == std::numeric_limits<double>::infinity() ||
         (around_.full() && nearest + around_.distance(k - 1) < reach);
}

void UnstructuredArchive::refill(Index count, const Real* solutions, const Real* objectives,
                                 const Real* descriptors, const Real* base_features, double threshold,
                                 std::vector<Index>* rows) {
  clear();
  if (rows) rows->clear();
  const Index d = params_.measure_size, g = params_.solution_size, b = params_.base_feature_size;
  // Rows up to the first non-finite descriptor go in, then that row's add() throws, as one by one.
  Index finite = 0;
  while (finite < count && std::all_of(descriptors + finite * d, descriptors + (finite + 1) * d,
                                       [](Real x) { return std::isfinite(x); }))
    ++finite;
  grid_.reserve(descriptors, finite);
  const std::vector<std::uint8_t>& apart = rows_apart_.find(descriptors, finite, d, threshold);
  for (Index i = 0; i < finite; ++i) {
    const Real* base = base_features ? base_features + i * b : nullptr;
    Index slot = size();
    if (apart[static_cast<std::size_t>(i)] || empty()) append(solutions + i * g, objectives[i], descriptors + i * d, base);
    else add_near(solutions + i * g, objectives[i], descriptors + i * d, base, threshold, &slot);
    if (rows && slot >= 0) {
      if (slot == static_cast<Index>(rows->size())) rows->push_back(i);
      else (*rows)[static_cast<std::size_t>(slot)] = i;
    }
  }
  if (finite < count) check_finite(descriptors + finite * d);
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
  grid_.insert(slot, descriptor);
}

void UnstructuredArchive::overwrite(Index slot, const Real* solution, Real objective, const Real* descriptor,
                                    const Real* base_features) {
  grid_.erase(slot);
  objectives_[static_cast<std::size_t>(slot)] = objective;
  std::copy_n(solution, params_.solution_size, solutions_.begin() + slot * params_.solution_size);
  if (params_.base_feature_size > 0 && base_features)
    std::copy_n(base_features, params_.base_feature_size, base_.begin() + slot * params_.base_feature_size);
  for (std::size_t j = 0; j < coordinates_.size(); ++j) coordinates_[j][static_cast<std::size_t>(slot)] = descriptor[j];
  grid_.insert(slot, descriptor);
}

void UnstructuredArchive::clear() {
  objectives_.clear();
  solutions_.clear();
  base_.clear();
  for (auto& c : coordinates_) c.clear();
  grid_.clear();
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
  out.value<std::int64_t>(params_.measure_size);
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
  if (dims != params_.measure_size || genes != params_.solution_size || base != params_.base_feature_size)
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
  // As add() requires of every elite: a saved state whose bytes were changed must not load a NaN.
  const auto finite = [](const std::vector<Real>& v) {
    return std::all_of(v.begin(), v.end(), [](Real x) { return std::isfinite(x); });
  };
  if (!finite(objectives) || !std::all_of(coordinates.begin(), coordinates.end(), finite))
    in.fail("unstructured archive: an elite has a non-finite objective or descriptor: the saved state is damaged");
  clear();
  std::vector<Real> descriptor(static_cast<std::size_t>(dims));
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < descriptor.size(); ++j) descriptor[j] = coordinates[j][i];
    append(solutions.data() + i * static_cast<std::size_t>(genes), objectives[i], descriptor.data(),
           base > 0 ? base_features.data() + i * static_cast<std::size_t>(base) : nullptr);
  }
}

}  // namespace qdmeta
