#pragma once
// The 0.2.0 place of run/run_directory.hpp and experiment/test_phase.hpp, kept for programs written then
// (CHANGELOG.md, "experiment/ split by job"); new code includes the new path.
#include "qdmeta/experiment/test_phase.hpp"
#include "qdmeta/run/run_directory.hpp"
