#include "qdmeta/cli/mpi_distribution.hpp"

#include <fmt/format.h>

#include <chrono>
#include <sstream>

#include "qdmeta/cli/distribution.hpp"
#include "qdmeta/eval/mpi/mpi_evaluator.hpp"
#include "qdmeta/eval/mpi/mpi_session.hpp"
#include "qdmeta/eval/mpi/mpi_worker.hpp"

namespace qdmeta {
namespace {

class MpiDistribution final : public Distribution {
 public:
  MpiDistribution(int& argc, char**& argv) : session_(argc, argv) {}

  int ranks() const override { return session_.size(); }

  // Ranks > 0 never parse the command line (rank 0 sends them its resolved config), so
  // messages come from rank 0 alone.
  std::optional<int> serve_if_worker() override {
    if (session_.rank() == 0) return std::nullopt;
    return run_mpi_worker(session_, [](const std::string& config) {
      return build_run(toml::parse(config), "the config from MPI rank 0", {}, BuildScope::kTasksOnly).evaluation_tasks;
    });
  }

  // MPI ranks when there is more than one (where `--threads 0` means one thread per rank, since
  // ranks usually fill the cores), else threads.
  std::unique_ptr<Evaluator> make_evaluator(const BuiltRun& built, int& threads, const std::atomic<bool>* stop) override {
    if (session_.size() < 2) return Distribution::make_evaluator(built, threads, stop);
    if (threads == 0) threads = 1;
    std::ostringstream config;
    config << built.resolved;
    return make_mpi_evaluator(session_, built.evaluation_tasks, config.str(), threads, stop);
  }

  // The ranks that rank 0 found dead, else those that did not say goodbye when the job was stopped.
  std::string silent_ranks() override {
    std::string who;
    if (session_.size() < 2) return who;
    const std::vector<int> silent = session_.silent_workers(std::chrono::milliseconds(300));
    // Some rank is gone or going: MPI_Finalize could wait for it forever. Otherwise only rank 0
    // was stopped (a signal to it alone): the workers are released and finalised as at a normal
    // end, so that none outlives the job.
    if (!silent.empty() || session_.any_farewell()) session_.abandon();
    for (int r : silent) who += fmt::format("{}{}", who.empty() ? "" : ", ", r);
    if (!who.empty())
      who = fmt::format("MPI rank{} {} stopped answering (crashed or killed); ", silent.size() > 1 ? "s" : "", who);
    return who;
  }

  void release_survivors() override { session_.release_survivors(); }

 private:
  MpiSession session_;
};

}  // namespace

std::unique_ptr<Distribution> make_mpi_distribution(int& argc, char**& argv) {
  return std::make_unique<MpiDistribution>(argc, argv);
}

}  // namespace qdmeta
