#include "qdmeta/run/run_outputs.hpp"

#include "qdmeta/io/csv.hpp"
#include "qdmeta/run/summary.hpp"

namespace qdmeta {

void RunOutputs::on_end(const RunStatus& status, const RunResult& result) {
  const Algorithm& algorithm = status.algorithm;
  write_elites_csv(dir_ / "archive.csv", algorithm.elites());
  write_summary(dir_ / "summary.json",
                {result, status.settings, algorithm.name(), threads_, algorithm.summary_extras()});
  if (result.reason == StopReason::kBudget) std::filesystem::remove(dir_ / kCheckpointFile);
}

}  // namespace qdmeta
