#pragma once
// What a valid [[claim]] table of an experiment file is (docs/config.md, "Experiment files and
// claims"), so that `qdmeta experiment` refuses a malformed claim before any run starts rather
// than the report failing after every run. The report checks the claims it reads with
// tools/claim_rules.py, in the same words; tests/data/claims/cases.toml keeps the two in agreement.
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace qdmeta {

// Throws InputError "FILE:LINE:COLUMN: [[claim]] N: rule" for the first rule a claim breaks:
// an unknown or missing key for its kind, a wrong type, an unknown measure, a condition that is
// not one of `conditions`, a test measure of a test not among `tests`.
void check_claims(const toml::array& claims, const std::vector<std::string>& conditions,
                  const std::vector<std::string>& tests, const std::string& file);

}  // namespace qdmeta
