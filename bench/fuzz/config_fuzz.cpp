// The config fuzzer at length (the suite runs 3,000 cases): build/bench/config_fuzz [cases] [seed]
// prints the outcome counts and every defect, and exits 1 when there is one.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "config_fuzzer.hpp"
#ifdef QDMETA_FUZZ_RHEX
#include "qdmeta/tasks/rhex/rhex_config.hpp"
#endif

int main(int argc, char** argv) {
#ifdef QDMETA_FUZZ_RHEX
  qdmeta::register_rhex_task();  // the RHex configs are then read as the CLI reads them
#endif
  const int cases = argc > 1 ? std::atoi(argv[1]) : 100'000;
  const auto seed = static_cast<std::uint64_t>(argc > 2 ? std::atoll(argv[2]) : 7);
  const auto seeds = qdmeta::fuzz::seed_configs(std::string(QDMETA_SOURCE_DIR) + "/configs");
  const auto r = qdmeta::fuzz::fuzz_configs(seeds, seed, cases);
  for (const auto& d : r.defects) std::printf("DEFECT:\n%s\n\n", d.c_str());
  std::printf("%d cases (seed %llu) from %zu configs: %d accepted (%d algorithms built), %d refused with a message, "
              "%zu defects; slowest case %.3f s\n",
              r.cases, static_cast<unsigned long long>(seed), seeds.size(), r.accepted, r.built_algorithms, r.refused,
              r.defects.size(), r.slowest_seconds);
  return r.defects.empty() ? 0 : 1;
}
