#include "qdmeta/archive/proximity_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("ProximityArchive: " + what);
}

bool all_finite(std::span<const double> values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

}  // namespace

void ProximityArchiveParams::validate() const {
  require(solution_size >= 1, fmt::format("solution_dim ({}) must be at least 1", solution_size));
  require(measure_size >= 1, fmt::format("measure_dim ({}) must be at least 1", measure_size));
  require(k_neighbors >= 1, fmt::format("k_neighbors ({}) must be at least 1", k_neighbors));
  require(std::isfinite(novelty_threshold) && novelty_threshold >= 0.0,
          fmt::format("novelty_threshold ({}) must be finite and >= 0", novelty_threshold));
  if (threshold_decay_rate) {
    require(*threshold_decay_rate > 0.0 && *threshold_decay_rate <= 1.0,
            fmt::format("threshold_decay_rate ({}) must be in (0, 1]", *threshold_decay_rate));
    require(threshold_decay_itrs >= 1,
            fmt::format("threshold_decay_itrs ({}) must be at least 1", threshold_decay_itrs));
    require(std::isfinite(threshold_decay_min) && threshold_decay_min >= 0.0,
            fmt::format("threshold_decay_min ({}) must be finite and >= 0", threshold_decay_min));
  }
  require(std::isfinite(qd_offset), "qd_score_offset must be finite");
}

ProximityArchive::ProximityArchive(const ProximityArchiveParams& params)
    : params_(params), threshold_(params.novelty_threshold) {
  params_.validate();
}

std::size_t ProximityArchive::nearest(const double* point, std::size_t k, std::vector<std::size_t>& elites,
                                      std::vector<double>& distances) const {
  elites.resize(k);
  distances.resize(k);
  const std::size_t found = tree_ ? tree_->nearest(point, k, elites.data(), distances.data()) : 0;
  for (std::size_t i = 0; i < found; ++i) distances[i] = std::sqrt(distances[i]);
  return found;
}

std::vector<double> ProximityArchive::novelty(std::span<const double> measures) const {
  const auto d = static_cast<std::size_t>(params_.measure_size);
  require(measures.size() % d == 0, fmt::format("measures has {} values, not n x measure_dim ({})", measures.size(), d));
  const std::size_t rows = measures.size() / d;
  std::vector<double> novelty(rows, threshold_);
  if (objectives_.empty()) return novelty;
  const auto k = std::min(static_cast<std::size_t>(params_.k_neighbors), objectives_.size());
  std::vector<std::size_t> elites;
  std::vector<double> dist;
  for (std::size_t r = 0; r < rows; ++r) {
    nearest(measures.data() + r * d, k, elites, dist);
    double sum = 0.0;
    for (std::size_t i = 0; i < k; ++i) sum += dist[i];
    novelty[r] = sum / static_cast<double>(k);
  }
  return novelty;
}

std::vector<Index> ProximityArchive::index_of(std::span<const double> measures) const {
  const auto d = static_cast<std::size_t>(params_.measure_size);
  require(measures.size() % d == 0, fmt::format("measures has {} values, not n x measure_dim ({})", measures.size(), d));
  require(!objectives_.empty(), "index_of needs at least one elite in the archive (the nearest one is the index)");
  std::vector<Index> cells(measures.size() / d);
  std::vector<std::size_t> elites;
  std::vector<double> dist;
  for (std::size_t r = 0; r < cells.size(); ++r) {
    nearest(measures.data() + r * d, 1, elites, dist);
    cells[r] = static_cast<Index>(elites[0]);
  }
  return cells;
}

void ProximityArchive::replace(Index elite, const double* solution, double objective, const double* measures) {
  const auto s = static_cast<std::size_t>(params_.solution_size);
  const auto d = static_cast<std::size_t>(params_.measure_size);
  const auto e = static_cast<std::size_t>(elite);
  std::copy(solution, solution + s, solutions_.begin() + static_cast<std::ptrdiff_t>(e * s));
  std::copy(measures, measures + d, measures_.begin() + static_cast<std::ptrdiff_t>(e * d));
  objectives_[e] = objective;
}

void ProximityArchive::append(const double* solution, double objective, const double* measures) {
  solutions_.insert(solutions_.end(), solution, solution + params_.solution_size);
  measures_.insert(measures_.end(), measures, measures + params_.measure_size);
  objectives_.push_back(objective);
}

void ProximityArchive::update_threshold(Index novel_added) {
  if (!params_.threshold_decay_rate) return;
  if (novel_added > 0) {
    adds_without_novel_ = 0;
    return;
  }
  if (++adds_without_novel_ < params_.threshold_decay_itrs) return;
  threshold_ = std::max(params_.threshold_decay_min, threshold_ * *params_.threshold_decay_rate);
  adds_without_novel_ = 0;
}

ProximityAddResult ProximityArchive::add(std::span<const double> solutions, std::span<const double> objectives,
                                         std::span<const double> measures) {
  const std::size_t rows = objectives.size();
  const auto s = static_cast<std::size_t>(params_.solution_size);
  const auto d = static_cast<std::size_t>(params_.measure_size);
  require(solutions.size() == rows * s,
          fmt::format("solution has {} values, not {} rows x solution_dim ({})", solutions.size(), rows, s));
  require(measures.size() == rows * d,
          fmt::format("measures has {} values, not {} rows x measure_dim ({})", measures.size(), rows, d));
  require(all_finite(objectives), "objective must be finite");
  require(all_finite(measures), "measures must be finite");

  ProximityAddResult result;
  result.status.assign(rows, 0);
  result.novelty = novelty(measures);
  std::vector<std::size_t> novel;
  for (std::size_t r = 0; r < rows; ++r)
    if (result.novelty[r] >= threshold_) novel.push_back(r);

  if (params_.local_competition) {
    result.local_competition.assign(rows, 0);
    result.value.assign(rows, 0.0);
    const bool had_elites = !objectives_.empty();
    const auto k = std::min(static_cast<std::size_t>(params_.k_neighbors), objectives_.size());
    std::vector<std::size_t> order;
    std::vector<double> dist;
    // Per elite, the candidate that replaces it: the best improving one, the first on ties.
    std::vector<std::ptrdiff_t> winner(objectives_.size(), -1);
    for (std::size_t r = 0; r < rows && had_elites; ++r) {
      nearest(measures.data() + r * d, k, order, dist);
      for (std::size_t i = 0; i < k; ++i) result.local_competition[r] += objectives_[order[i]] < objectives[r] ? 1 : 0;
      if (result.novelty[r] >= threshold_) {
        result.value[r] = objectives[r];
        continue;
      }
      const std::size_t closest = order[0];
      result.value[r] = objectives[r] - objectives_[closest];
      if (objectives[r] > objectives_[closest]) {
        result.status[r] = 1;
        std::ptrdiff_t& w = winner[closest];
        if (w < 0 || objectives[r] > objectives[static_cast<std::size_t>(w)]) w = static_cast<std::ptrdiff_t>(r);
      }
    }
    if (!had_elites)
      for (std::size_t r : novel) result.value[r] = objectives[r];
    for (std::size_t e = 0; e < winner.size(); ++e)
      if (winner[e] >= 0) {
        const auto r = static_cast<std::size_t>(winner[e]);
        replace(static_cast<Index>(e), solutions.data() + r * s, objectives[r], measures.data() + r * d);
      }
  }
  for (std::size_t r : novel) {
    result.status[r] = 2;
    append(solutions.data() + r * s, objectives[r], measures.data() + r * d);
  }
  const bool replaced = std::find(result.status.begin(), result.status.end(), 1) != result.status.end();
  if (replaced || !novel.empty())
    tree_ = std::make_shared<const KdTree>(measures_, static_cast<std::size_t>(params_.measure_size));
  update_threshold(static_cast<Index>(novel.size()));
  return result;
}

void ProximityArchive::save(BinaryWriter& out) const {
  out.tag("proximity archive");
  out.value(static_cast<std::int64_t>(params_.solution_size));
  out.value(static_cast<std::int64_t>(params_.measure_size));
  out.value(threshold_);
  out.value(static_cast<std::int64_t>(adds_without_novel_));
  out.values(solutions_);
  out.values(objectives_);
  out.values(measures_);
}

void ProximityArchive::load(BinaryReader& in) {
  in.expect_tag("proximity archive");
  const auto s = in.value<std::int64_t>("proximity solution size");
  const auto d = in.value<std::int64_t>("proximity measure size");
  if (s != params_.solution_size || d != params_.measure_size)
    in.fail(fmt::format("the saved proximity archive has {} genes and {} measures; this one {} and {}", s, d,
                        params_.solution_size, params_.measure_size));
  const auto threshold = in.value<double>("novelty threshold");
  const auto without_novel = in.value<std::int64_t>("adds without a novel one");
  auto solutions = in.values<double>("proximity solutions");
  auto objectives = in.values<double>("proximity objectives");
  auto measures = in.values<double>("proximity measures");
  const std::size_t n = objectives.size();
  if (solutions.size() != n * static_cast<std::size_t>(s) || measures.size() != n * static_cast<std::size_t>(d))
    in.fail(fmt::format("the saved proximity archive's solutions or measures do not fit its {} elites", n));
  const auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (!std::isfinite(threshold) || threshold < 0.0 || without_novel < 0 || !finite(solutions) || !finite(objectives) ||
      !finite(measures))
    in.fail("the saved proximity archive holds a value out of range or not finite: the saved state is damaged");
  threshold_ = threshold;
  adds_without_novel_ = static_cast<Index>(without_novel);
  solutions_ = std::move(solutions);
  objectives_ = std::move(objectives);
  measures_ = std::move(measures);
  tree_ = n == 0 ? nullptr : std::make_shared<const KdTree>(measures_, static_cast<std::size_t>(params_.measure_size));
}

ArchiveStats ProximityArchive::stats() const {
  return archive_stats(
      [&](auto&& visit) {
        for (double f : objectives_) visit(f);
      },
      std::max<double>(1.0, static_cast<double>(objectives_.size())), params_.qd_offset);
}

}  // namespace qdmeta
