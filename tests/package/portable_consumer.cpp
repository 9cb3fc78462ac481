// Runs a config to its budget through the library and writes the algorithm's elites as
// archive.csv, so that the installed-package test can compare them with `qdmeta run`'s. Built
// for another instruction set than the library: the elite table is allocated by the library and
// freed here, which aborted with "double free or corruption" while Eigen's heap allocator
// followed each side's instruction set (docs/library.md, "Portable programs"). Eigen comes first,
// as clang-format sorts it: the qdmeta target's definitions configure it, whatever the order.
#include <Eigen/Dense>
#include <qdmeta/assembly/build.hpp>
#include <qdmeta/eval/evaluator.hpp>
#include <qdmeta/io/csv.hpp>

#include <cstdio>
#include <exception>
#include <string>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: portable-consumer CONFIG EVALUATIONS ARCHIVE_CSV\n");
    return 2;
  }
  try {
    qdmeta::Overrides overrides;
    overrides.evaluations = std::stoll(argv[2]);
    qdmeta::BuiltRun run = qdmeta::build_run(toml::parse_file(argv[1]), argv[1], overrides);
    const auto evaluator = qdmeta::make_evaluator(1);
    while (run.settings.evals(run.algorithm->counters()) < run.settings.budget) run.algorithm->step(*evaluator);
    const qdmeta::EliteTable first = run.algorithm->elites();
    const Eigen::MatrixX<qdmeta::Real> solutions = first.solutions;  // a column-major copy, made here
    qdmeta::write_elites_csv(argv[3], first);
    qdmeta::EliteTable again = run.algorithm->elites();
    const bool same = again.size() == first.size() && Eigen::MatrixX<qdmeta::Real>(again.solutions) == solutions;
    again = qdmeta::EliteTable{};  // frees the library's allocation here; `first` at the end
    if (!same || again.solutions.size() != 0) {
      std::fprintf(stderr, "portable-consumer: elites() gave two different tables\n");
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "portable-consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
