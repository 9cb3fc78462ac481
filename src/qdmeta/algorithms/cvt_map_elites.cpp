#include "qdmeta/algorithms/cvt_map_elites.hpp"

#include <fmt/format.h>

#include <functional>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/parallel.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void CvtMapElitesParams::validate() const {
  map_elites.validate();
  kmeans.validate();
  require(kLookupChunk, lookup_chunk);
  require(kNeighbours, neighbours);
}

CvtSearch resolve_cvt_search(CvtSearch search, Index dimensions) {
  if (search != CvtSearch::kAuto) return search;
  return dimensions > CentroidGrid::kMaxDimensions ? CvtSearch::kParentBound : CvtSearch::kBruteForce;
}

void add_cvt_map_elites_memory(MemoryEstimate& m, const CvtMapElitesParams& p, const Task& task) {
  constexpr auto kFloat = static_cast<double>(sizeof(Real));
  const auto cells = static_cast<double>(p.kmeans.centroids);
  const auto nb = static_cast<double>(task.base_feature_size());
  const double lists = resolve_cvt_search(p.search, task.base_feature_size()) == CvtSearch::kParentBound
                           ? static_cast<double>(std::min(p.neighbours, p.kmeans.centroids)) * sizeof(Index)
                           : 0.0;
  m.add("the archive and its neighbour lists", "cvt.centroids x (genes + base features + cvt.neighbours)",
        cells * (kFloat + 1 + kFloat * (static_cast<double>(task.genotype_size()) + 2 * nb) + lists));
  m.add("k-means's points", "cvt.samples x base features",
        static_cast<double>(p.kmeans.samples) * (kFloat * nb + sizeof(Index) + sizeof(float)) +
            static_cast<double>(std::min(p.kmeans.init_samples, p.kmeans.samples)) * sizeof(Index));
  add_map_elites_memory(m, p.map_elites, task);
}

CvtMapElites::CvtMapElites(CvtMapElitesParams params, Task task, MutationParams mutation, std::uint64_t seed)
    : params_(std::move(params)),
      task_(std::move(task)),
      mutation_(mutation),
      seed_(seed),
      search_(resolve_cvt_search(params_.search, task_.base_feature_size())) {
  params_.validate();
  if (params_.centroids) give_centroids(params_.centroids);
}

void CvtMapElites::give_centroids(std::shared_ptr<const RowMatrix> centroids) {
  if (archive_) throw Error("cvt-map-elites: centroids can be given only before the archive is made");
  if (!centroids || centroids->rows() != params_.kmeans.centroids || centroids->cols() != task_.base_feature_size())
    throw InputError(fmt::format("cvt-map-elites: the given centroids are {} x {}, expected cvt.centroids x base "
                                 "features = {} x {}",
                                 centroids ? centroids->rows() : 0, centroids ? centroids->cols() : 0,
                                 params_.kmeans.centroids, task_.base_feature_size()));
  params_.centroids = std::move(centroids);
}

void CvtMapElites::prepare(Evaluator& evaluator) { make_archive(&evaluator); }

void CvtMapElites::make_archive(Evaluator* workers) {
  if (archive_) return;
  const Index lists = search_ == CvtSearch::kParentBound ? params_.neighbours : 0;
  if (!params_.centroids) {
    RowMatrix made;
    if (params_.make_centroids) {
      made = params_.make_centroids(workers);
    } else {
      const auto uniform = [&] { made = cvt_centroids(task_.base_feature_size(), params_.kmeans).centroids; };
      if (workers != nullptr) workers->within_workers(uniform);
      else uniform();
    }
    give_centroids(std::make_shared<const RowMatrix>(std::move(made)));
  }
  archive_.emplace(CvtArchiveParams{task_.genotype_size(), task_.qd_offset(), lists}, RowMatrix(*params_.centroids));
}

const CvtArchive& CvtMapElites::archive() const {
  if (!archive_) throw Error("cvt-map-elites: the archive is made by the first step (or prepare())");
  return *archive_;
}

void CvtMapElites::before_step(Evaluator& evaluator) { prepare(evaluator); }

void CvtMapElites::next_request(std::vector<EvaluationJob>& jobs) {
  // Driven by hand without prepare(), the centroids are made on one thread (the same bits).
  if (!archive_) make_archive(nullptr);
  const Index n = task_.genotype_size();
  next_genotypes(*archive_, params_.map_elites, mutation_, seed_, generation_, n, genotypes_, &parents_);
  evaluations_.resize(genotypes_.rows(), task_.base_feature_size());
  jobs.push_back({&task_, {genotypes_.data(), genotypes_.rows(), n}, evaluations_.view()});
}


bool CvtMapElites::take_results() {
  CvtArchive& archive = *archive_;
  const Index count = genotypes_.rows();
  // Cells in parallel over fixed row ranges (each row's cell does not depend on the split);
  // then the neighbour lists of the rows that may enter (judged against the archive before the
  // batch: a superset of those that will), in parallel; then insertion in batch order.
  // Invalid rows get a cell too, never used: their base features (which a task may leave
  // undefined, even NaN) are zeroed first.
  for (Index r = 0; r < count; ++r)
    if (!evaluations_.valid[static_cast<std::size_t>(r)]) evaluations_.base_features.row(r).setZero();
  cells_.resize(static_cast<std::size_t>(count));
  settled_.assign(static_cast<std::size_t>(count), 0);
  const Index* parents = search_ == CvtSearch::kParentBound ? parents_.data() : nullptr;
  const Index chunk = params_.lookup_chunk;
  const Index chunks = (count + chunk - 1) / chunk;
  searched_per_chunk_.assign(static_cast<std::size_t>(chunks), 0);
  parallel_indices(chunks, [&](Index c) {
    const Index first = c * chunk;
    searched_per_chunk_[static_cast<std::size_t>(c)] =
        archive.locate(evaluations_.base_features.row(first).data(), std::min(chunk, count - first),
                       parents ? parents + first : nullptr, cells_.data() + first, settled_.data() + first);
  });
  for (Index n_searched : searched_per_chunk_) searched_ += n_searched;
  entering_.clear();
  for (Index r = 0; r < count; ++r) {
    const auto u = static_cast<std::size_t>(r);
    if (evaluations_.valid[u] && archive.would_enter(cells_[u], evaluations_.fitness[r])) entering_.push_back(r);
  }
  lists_.resize(count, archive.list_length());
  if (archive.list_length() > 0) {
    // Parents' lists where they serve; the rest are remade together, at most kValueRows per task
    // (the centroids streamed once per block; blocks depend on the batch only, not the threads).
    const auto entering = static_cast<Index>(entering_.size());
    remade_.assign(entering_.size(), 0);
    parallel_indices((entering + chunk - 1) / chunk, [&](Index c) {
      for (Index i = c * chunk; i < std::min(entering, (c + 1) * chunk); ++i) {
        const Index r = entering_[static_cast<std::size_t>(i)];
        const auto u = static_cast<std::size_t>(r);
        remade_[static_cast<std::size_t>(i)] =
            !archive.inherit_list(evaluations_.base_features.row(r).data(), settled_[u] ? parents_[u] : -1, lists_, r);
      }
    });
    remade_rows_.clear();
    for (Index i = 0; i < entering; ++i)
      if (remade_[static_cast<std::size_t>(i)]) remade_rows_.push_back(entering_[static_cast<std::size_t>(i)]);
    const auto remade = static_cast<Index>(remade_rows_.size());
    const Index d = task_.base_feature_size();
    remade_points_.resize(remade, d);
    for (Index i = 0; i < remade; ++i) remade_points_.row(i) = evaluations_.base_features.row(remade_rows_[static_cast<std::size_t>(i)]);
    // An even number of blocks of near-equal size (about 18 remakes per batch of 400: blocks of
    // 5, 5, 5, 3 rather than 8, 8, 2), so that two workers share them evenly.
    const Index blocks = 2 * ((remade + 2 * kValueRows - 1) / (2 * kValueRows));
    const Index per_block = blocks > 0 ? (remade + blocks - 1) / blocks : 0;
    parallel_indices(blocks, [&](Index b) {
      const Index first = b * per_block, rows = std::min(per_block, remade - first);
      if (rows > 0) archive.remake_lists(remade_points_.row(first).data(), rows, remade_rows_.data() + first, lists_);
    });
  }
  for (Index r : entering_)
    archive.add_to_cell(cells_[static_cast<std::size_t>(r)], genotypes_.row(r).data(), evaluations_.fitness[r],
                        evaluations_.base_features.row(r).data(), lists_, r);
  ++generation_;
  return true;
}

ArchiveStats CvtMapElites::stats() const { return archive_ ? archive_->stats() : ArchiveStats{}; }

EliteTable CvtMapElites::elites() const { return archive_ ? archive_->elites() : EliteTable{}; }

void CvtMapElites::save(BinaryWriter& out) const {
  require_between_steps("save()");
  out.tag("cvt_map_elites");
  out.value(generation_);
  out.value(searched_);
  save_counters(out, counters());
  out.boolean(archive_.has_value());
  if (archive_) archive_->save(out);
}

void CvtMapElites::load(BinaryReader& in) {
  require_between_steps("load()");
  in.expect_tag("cvt_map_elites");
  generation_ = in.value<std::int64_t>("generation");
  searched_ = in.value<std::int64_t>("searched count");
  restore_counters(load_counters(in));
  if (in.boolean("archive flag")) {
    make_archive(nullptr);
    archive_->load(in);
  }
}

}  // namespace qdmeta
