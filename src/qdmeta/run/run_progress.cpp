#include "qdmeta/run/run_progress.hpp"

namespace qdmeta {

RunVerdict ProgressReporter::after_step(const RunStatus& status) {
  callback_({status.evals, status.settings.budget, status.algorithm.generation(), status.clock.seconds(),
             &status.algorithm});
  return RunVerdict::kContinue;
}

}  // namespace qdmeta
