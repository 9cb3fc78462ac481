// qdmeta's command line with two faulty tasks, as a user's first C++ task can be: "throws"
// throws from its own code once `throw_after` rows were evaluated, "never-valid" never sets a
// row's valid flag. tests/cli/task_failure_test.cpp runs them.
#include <atomic>
#include <stdexcept>

#include "qdmeta/cli/builtin_plugins.hpp"
#include "qdmeta/cli/run_cli.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/task_registry.hpp"

namespace {

struct ThrowingTask {
  qdmeta::Index after = 0;
  std::string name() const { return "throws"; }
  qdmeta::Index genotype_size() const { return 2; }
  qdmeta::Index base_feature_size() const { return 2; }
  void evaluate(qdmeta::GenotypeView genotypes, qdmeta::EvaluationView out) const {
    static std::atomic<qdmeta::Index> rows{0};
    for (qdmeta::Index i = 0; i < genotypes.count; ++i) {
      if (rows++ >= after) throw std::runtime_error("simulator diverged");
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
    return qdmeta::Task(ThrowingTask{table.integer("throw_after", 0, 0, 1'000'000'000)});
  };
  qdmeta::register_task_plugin("throws", std::move(throws));
  qdmeta::TaskPlugin never;
  never.read_task = [](qdmeta::ConfigReader&) { return qdmeta::Task(NeverValidTask{}); };
  qdmeta::register_task_plugin("never-valid", std::move(never));
  return qdmeta::run_cli(argc, argv);
}
