#pragma once
// The 0.2.0 place of run/run.hpp, kept for programs written then
// (CHANGELOG.md, "experiment/ split by job"); new code includes the new path.
#include "qdmeta/run/run.hpp"
