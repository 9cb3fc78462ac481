// qdmeta's command line with two faulty tasks, as a user's first C++ task can be: "throws"
// throws from its own code once `throw_after` rows were evaluated (by this process; with
// `throw_on_rank = R` only on MPI rank R, as OpenMPI numbers it), "never-valid" never sets a
// row's valid flag. tests/cli/task_failure_test.cpp and mpi_cli_test.cpp run them.
#include <atomic>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "qdmeta/cli/builtin_plugins.hpp"
#include "qdmeta/cli/run_cli.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/task_registry.hpp"

namespace {

// This process's MPI rank as OpenMPI's launcher sets it, -1 outside mpirun.
long mpi_rank() {
  const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
  return rank == nullptr ? -1 : std::atol(rank);
}

struct ThrowingTask {
  qdmeta::Index after = 0;
  bool throws_here = true;
  std::string name() const { return "throws"; }
  qdmeta::Index genotype_size() const { return 2; }
  qdmeta::Index base_feature_size() const { return 2; }
  void evaluate(qdmeta::GenotypeView genotypes, qdmeta::EvaluationView out) const {
    static std::atomic<qdmeta::Index> rows{0};
    for (qdmeta::Index i = 0; i < genotypes.count; ++i) {
      if (rows++ >= after && throws_here) throw std::runtime_error("simulator diverged");
      out.fitness[i] = 0;
      out.base_row(i)[0] = genotypes.row(i)[0];
      out.base_row(i)[1] = genotypes.row(i)[1];
      out.valid[i] = 1;
    }
  }
};

struct NeverValidTask {
  std::string name() const { return "never-valid"; }
  qdmeta::Index genotype_size() const { return 2; }
  qdmeta::Index base_feature_size() const { return 2; }
  void evaluate(qdmeta::GenotypeView genotypes, qdmeta::EvaluationView out) const {
    for (qdmeta::Index i = 0; i < genotypes.count; ++i) {
      out.fitness[i] = 1;
      out.base_row(i)[0] = out.base_row(i)[1] = 0.5f;  // valid left unset (0)
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  qdmeta::register_builtin_plugins();
  qdmeta::TaskPlugin throws;
  throws.read_task = [](qdmeta::ConfigReader& table) {
    const auto after = table.integer("throw_after", 0, 0, 1'000'000'000);
    const auto rank = table.integer("throw_on_rank", -1, -1, 1'000'000);
    return qdmeta::Task(ThrowingTask{after, rank < 0 || rank == mpi_rank()});
  };
  qdmeta::register_task_plugin("throws", std::move(throws));
  qdmeta::TaskPlugin never;
  never.read_task = [](qdmeta::ConfigReader&) { return qdmeta::Task(NeverValidTask{}); };
  qdmeta::register_task_plugin("never-valid", std::move(never));
  return qdmeta::run_cli(argc, argv);
}
