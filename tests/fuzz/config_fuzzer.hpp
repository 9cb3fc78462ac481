#pragma once
// A config fuzzer over the TOML reader and the run builder: shipped configs, mutated at random
// (keys removed, values replaced by extreme, wrong-typed or malformed ones, unknown keys added,
// bytes of the text flipped, inserted or deleted, NUL bytes, table headers, dotted keys and values
// nested up to 100,000 deep), each read (as a config file is) and built in process. A case may be
// accepted or refused with an InputError; anything else is a defect: another exception
// (std::bad_alloc included), a crash (the sanitizers report it), or a case slower than the limit.
#include <cstdint>
#include <string>
#include <vector>

namespace qdmeta::fuzz {

struct FuzzReport {
  int cases = 0;
  int accepted = 0;  // built (tasks only; the algorithm too when its memory estimate is small)
  int refused = 0;   // InputError: the message the user would see
  int built_algorithms = 0;
  double slowest_seconds = 0;
  std::string slowest_case;
  std::vector<std::string> defects;  // "case text\n=> what happened"
};

// The config texts the mutations start from: every file under `configs_dir` (recursively).
std::vector<std::string> seed_configs(const std::string& configs_dir);

// Runs `cases` mutated configs drawn from `seed`; every case is reproducible from (seed, index).
FuzzReport fuzz_configs(const std::vector<std::string>& seeds, std::uint64_t seed, int cases);

}  // namespace qdmeta::fuzz
