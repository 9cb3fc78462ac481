#pragma once
// The resolved config fingerprint: what makes the runs of one condition comparable. An
// experiment run again after a condition's config changed must not continue (or keep) runs made
// with the old one beside runs made with the new one, so every run directory, kept summary and
// plan row carries this hash of the condition's config, and `qdmeta experiment` (and `qdmeta
// report`, tools/report.py) compare it.
//
// The hash covers the fully resolved config (every key in force, defaults included, an
// experiment file's `set` and budget merged in), less what legitimately differs between the
// replicates of one condition or changes no result:
//   seed                     each replicate's own
//   [provenance]             program version, config file, threads: how, not what
//   [checkpoint]             when checkpoints are written (the results are the same bits)
//   cvt.cache, cvt.cache_dir where k-means centroids are cached (they are keyed by their parameters)
// It is 16 lowercase hex digits (FNV-1a, 64 bits, of the remaining config as TOML text), stored
// as provenance.config_fingerprint in a run's config.toml and as the top-level key
// "config_fingerprint" of a kept summary (docs/config.md, "Experiments").
#include <cstdint>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace qdmeta {

inline constexpr const char* kConfigFingerprintKey = "config_fingerprint";

// Fingerprint of a resolved config (without its [provenance] table): a checkpoint
// (run/checkpoint.hpp) only continues the run it was written for. Unlike the resolved config
// fingerprint below, it covers the seed and every other key.
std::uint64_t config_fingerprint(const toml::table& resolved);

// The part of a resolved config that the fingerprint covers (the exclusions above removed).
toml::table fingerprinted_config(const toml::table& resolved);

// The fingerprint of a resolved config: 16 lowercase hex digits.
std::string resolved_config_fingerprint(const toml::table& resolved);

// Whether `text` has the form of a fingerprint (16 lowercase hex digits).
bool is_config_fingerprint(const std::string& text);

// The dotted keys (e.g. "mutation.sigma") whose values differ between the fingerprinted parts of
// two resolved configs, a key in only one of them included; in key order.
std::vector<std::string> differing_keys(const toml::table& a, const toml::table& b);

// Keys for a message: "mutation.sigma differs", "mutation.sigma, budget.evaluations differ", the
// first few and "and N more".
std::string keys_that_differ(const std::vector<std::string>& keys);

}  // namespace qdmeta
