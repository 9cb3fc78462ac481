#include "qdmeta/experiment/adaptation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/io/table.hpp"

namespace qdmeta {

AdaptationCurve random_search_adaptation(const RowMatrix& archive, const AdaptationTests& tests, Index budget,
                                         std::uint64_t seed, Evaluator& evaluator) {
  if (archive.rows() < 1) throw InputError(fmt::format("test '{}': the archive is empty", tests.name()));
  if (budget < 1) throw InputError(fmt::format("test '{}': budget {} must be at least 1", tests.name(), budget));
  const Index functions = tests.count();
  if (functions < 1) throw InputError(fmt::format("test '{}' has no test functions", tests.name()));
  // A best-so-far value per function and evaluation is kept: bound them before allocating.
  constexpr Index kMaxCurveValues = 100'000'000;
  if (budget > kMaxCurveValues / functions)
    throw InputError(fmt::format("test '{}': budget {} is more than its curves can hold ({} functions x budget may be at "
                                 "most 10^8; past the archive's {} solutions a curve only repeats its last value)",
                                 tests.name(), budget, functions, archive.rows()));
  const Index tried = std::min(budget, archive.rows());
  const auto b = static_cast<std::size_t>(budget);

  std::vector<std::vector<double>> best(static_cast<std::size_t>(functions), std::vector<double>(b));
  std::vector<std::size_t> order;
  RowMatrix chosen(tried, archive.cols());
  std::vector<double> scores(static_cast<std::size_t>(tried));
  for (Index t = 0; t < functions; ++t) {
    Rng rng = Rng::stream(seed, {key(StreamKey::kTest), static_cast<std::uint64_t>(t)});
    order.resize(static_cast<std::size_t>(archive.rows()));
    std::iota(order.begin(), order.end(), std::size_t{0});
    choose_without_replacement(order, static_cast<std::size_t>(tried), rng);
    for (Index k = 0; k < tried; ++k) chosen.row(k) = archive.row(static_cast<Index>(order[static_cast<std::size_t>(k)]));
    tests.score(t, chosen, evaluator, scores);
    auto& curve = best[static_cast<std::size_t>(t)];
    double so_far = -INFINITY;
    for (std::size_t e = 0; e < b; ++e) {
      if (e < scores.size()) {
        if (!std::isfinite(scores[e]))
          throw Error(fmt::format("test '{}' function {} scored {} for an archive solution", tests.name(), t, scores[e]));
        so_far = std::max(so_far, scores[e]);
      }
      curve[e] = so_far;  // past the archive's end the best stays
    }
  }

  AdaptationCurve out;
  out.best_mean.resize(b);
  out.best_se.resize(b);
  const auto n = static_cast<double>(functions);
  for (std::size_t e = 0; e < b; ++e) {
    double sum = 0.0;
    for (const auto& curve : best) sum += curve[e];
    const double mean = sum / n;
    double sq = 0.0;
    for (const auto& curve : best) sq += (curve[e] - mean) * (curve[e] - mean);
    out.best_mean[e] = mean;
    out.best_se[e] = functions > 1 ? std::sqrt(sq / (n - 1.0)) / std::sqrt(n) : 0.0;
  }
  for (const auto& curve : best) out.final_best.push_back(curve.back());
  return out;
}

namespace {

// One point of an adaptation curve: the best after `e + 1` evaluations.
struct CurvePoint {
  const AdaptationCurve& curve;
  std::size_t e;
};

const Table<CurvePoint>& adaptation_table() {
  static const Table<CurvePoint> table = {
      {"evaluations", [](const CurvePoint& p) { return Cell(static_cast<std::uint64_t>(p.e + 1)); }},
      {"best_mean", [](const CurvePoint& p) { return Cell(p.curve.best_mean[p.e]); }},
      {"best_se", [](const CurvePoint& p) { return Cell(p.curve.best_se[p.e]); }},
  };
  return table;
}

const Table<GeneralisationRow>& generalisation_table() {
  static const Table<GeneralisationRow> table = {
      {"group", [](const GeneralisationRow& r) { return Cell(r.group); }},
      {"environments", [](const GeneralisationRow& r) { return Cell(std::int64_t{r.environments}); }},
      {"solutions", [](const GeneralisationRow& r) { return Cell(std::int64_t{r.solutions}); }},
      {"mean", [](const GeneralisationRow& r) { return Cell(r.mean); }},
      {"se", [](const GeneralisationRow& r) { return Cell(r.se); }},
  };
  return table;
}

}  // namespace

void write_adaptation_csv(const std::filesystem::path& path, const AdaptationCurve& curve) {
  std::string text = csv_line(adaptation_table().header());
  for (std::size_t e = 0; e < curve.best_mean.size(); ++e) text += csv_line(adaptation_table().row({curve, e}));
  write_file_atomic(path, text);
}

GeneralisationRow whole_archive_mean(const RowMatrix& archive, const AdaptationTests& tests, Evaluator& evaluator) {
  if (archive.rows() < 1) throw InputError(fmt::format("test '{}': the archive is empty", tests.name()));
  const Index envs = tests.count();
  if (envs < 1) throw InputError(fmt::format("test '{}' has no test functions", tests.name()));
  std::vector<double> scores(static_cast<std::size_t>(archive.rows()));
  std::vector<double> env_means;
  for (Index t = 0; t < envs; ++t) {
    tests.score(t, archive, evaluator, scores);
    double sum = 0.0;
    for (double v : scores) {
      if (!std::isfinite(v))
        throw Error(fmt::format("test '{}' function {} scored {} for an archive solution", tests.name(), t, v));
      sum += v;
    }
    env_means.push_back(sum / static_cast<double>(archive.rows()));
  }
  const auto n = static_cast<double>(envs);
  double mean = 0.0;
  for (double m : env_means) mean += m;
  mean /= n;
  double sq = 0.0;
  for (double m : env_means) sq += (m - mean) * (m - mean);
  return {tests.name(), envs, archive.rows(), mean, envs > 1 ? std::sqrt(sq / (n - 1.0)) / std::sqrt(n) : 0.0};
}

void write_generalisation_csv(const std::filesystem::path& path, const std::vector<GeneralisationRow>& rows) {
  std::string text = csv_line(generalisation_table().header());
  for (const auto& r : rows) text += csv_line(generalisation_table().row(r));
  write_file_atomic(path, text);
}

}  // namespace qdmeta
