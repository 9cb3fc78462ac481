#pragma once
// The test phase run on a finished run directory (`qdmeta adapt`, `qdmeta experiment`): its
// archive.csv under one of the task's test families, written beside the run as adapt-NAME.csv or
// generalisation.csv.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "qdmeta/archive/elite_table.hpp"
#include "qdmeta/experiment/adaptation.hpp"
#include "qdmeta/run/run_state.hpp"

namespace qdmeta {

struct AdaptationReport {
  AdaptationCurve curve;
  Index functions = 0;
  Index budget = 0;
  Index archive_size = 0;
  std::filesystem::path file;  // the adapt-NAME.csv written
};

// The test phase on the finished run in `state` (`qdmeta adapt`): its archive.csv under the
// task's test family `test`; the budget defaults to the task's, the seed to the run's. A caller
// that holds the archive the run just wrote passes it as `archive` (the same values: archive.csv
// keeps every float to the bit), so that it is not read back.
AdaptationReport adapt_run(const RunState& state, std::string_view test, std::optional<Index> budget,
                           std::optional<std::uint64_t> seed, Evaluator& evaluator, const EliteTable* archive = nullptr);

struct GeneralisationReport {
  std::vector<GeneralisationRow> rows;
  Index archive_size = 0;
  std::filesystem::path file;  // the generalisation.csv written
};

// The generalisation test on the finished run in `state` (`qdmeta adapt --test generalisation`):
// the mean score of its whole archive.csv over each of the task's generalisation groups, or of
// `solutions` of them drawn without replacement from the seed (a small experiment's budget).
// `archive`: as adapt_run's.
GeneralisationReport generalise_run(const RunState& state, std::optional<std::uint64_t> seed,
                                    Evaluator& evaluator, std::optional<Index> solutions = std::nullopt,
                                    const EliteTable* archive = nullptr);

}  // namespace qdmeta
