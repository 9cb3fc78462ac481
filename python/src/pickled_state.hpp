#pragma once
// What an unpickled qdmeta state must pass before it is used. A pickle has no checksum of its
// own, so a flipped bit would load as other data (another objective, gene or seed): each state
// carries the checkpoint's checksum (FNV-1a, core/binary_io.hpp) over its values. An algorithm's
// state is also value-checked as a run's archive is (genes and base features in [0, 1]; every
// archive's load refuses a non-finite objective or measure).
#include <pybind11/pybind11.h>

#include <cstdint>
#include <initializer_list>
#include <string_view>

#include "qdmeta/archive/elite_table.hpp"

namespace qdmeta::python {

// The checksum of `parts` by value: None, bool, int, float, str, bytes, list, tuple, dict and
// numpy arrays (dtype, shape and bytes); anything else is an Error.
std::uint64_t state_checksum(std::initializer_list<pybind11::handle> parts);

// InputError naming `who` unless `stored` (the state's checksum) is the int `expected`.
void check_state_checksum(pybind11::handle stored, std::uint64_t expected, std::string_view who);

// InputError naming `who` unless every elite's genes and base features lie in [0, 1].
void check_run_elites(const EliteTable& elites, std::string_view who);

}  // namespace qdmeta::python
