#pragma once
// Simulated Binary Crossover (SBX; Deb & Agrawal 1995) bounded to the genes' range [0, 1], as a
// variation operator (qdmeta/core/variation.hpp): `[mutation] kind = "sbx"` in arm-qd's configs.
// Each gene of an offspring is, with probability 1/2, its parent's gene; otherwise one of the two
// SBX children of the parent's and the partner's gene, either with probability 1/2. The children
// lie at mean -/+ beta (distance / 2) of the two genes, with a spread factor beta whose density
// falls off as a power of `eta` away from 1 (the larger eta, the nearer the parents), truncated so
// that neither child leaves [0, 1].
#include <qdmeta/core/task.hpp>
#include <qdmeta/core/variation.hpp>
#include <qdmeta/plugin/config.hpp>

namespace arm {

// The operator with distribution index `eta` (> 0).
qdmeta::VariationFunction sbx(double eta);

// [mutation] kind = "sbx": key `eta` (default 20, > 0).
qdmeta::VariationFunction read_sbx(qdmeta::ConfigReader& mutation, const qdmeta::Task& task);

// Makes `[mutation] kind = "sbx"` available to configs (qdmeta's variation registry).
void register_sbx();

}  // namespace arm
