#pragma once
// The 0.2.0 place of assembly/run_parts.hpp, kept for programs written then
// (CHANGELOG.md, "experiment/ split by job"); new code includes the new path.
#include "qdmeta/assembly/run_parts.hpp"
