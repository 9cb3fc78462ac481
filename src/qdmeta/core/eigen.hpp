#pragma once
// Eigen, configured the same way in qdmeta and in every program built against it, whatever
// instruction set each is compiled for. The qdmeta CMake target passes the three settings below
// as compile definitions to every program that links it, so a file may include Eigen before
// qdmeta; every qdmeta header that uses Eigen also includes this one first, for a file compiled
// without them. Matrices cross the boundary both ways (a task's batches, a
// meta-objective's genotypes freed by QD-Meta, the table from elites() freed by the caller), so
// two things that Eigen otherwise derives from the instruction set must agree on both sides:
// - the alignment of fixed-size types, which sets the layout of every struct holding one: 16
//   bytes, what the prebuilt DART (SSE2) was compiled with;
// - the heap allocator: by default Eigen calls plain malloc where malloc's 16 bytes suffice
//   (SSE2) and its own aligned allocator, which stores the original pointer before the block,
//   with AVX; memory allocated by one and freed by the other is a double free. Eigen's aligned
//   allocator everywhere: each side aligns a block for its own vector width, and either side
//   frees it (a conservativeResize() must stay on the side that allocated the block).
#ifndef EIGEN_MAX_ALIGN_BYTES
#define EIGEN_MAX_ALIGN_BYTES 16
#endif
#ifndef EIGEN_MAX_STATIC_ALIGN_BYTES
#define EIGEN_MAX_STATIC_ALIGN_BYTES 16
#endif
#ifndef EIGEN_MALLOC_ALREADY_ALIGNED
#define EIGEN_MALLOC_ALREADY_ALIGNED 0
#endif

#include <Eigen/Core>

// Refused at compile time what would fail at run time: a file built without qdmeta's target (or
// with other values) that included Eigen first, with Eigen's settings for its instruction set.
#if EIGEN_MAX_ALIGN_BYTES != 16 || EIGEN_MAX_STATIC_ALIGN_BYTES != 16 || EIGEN_MALLOC_ALREADY_ALIGNED != 0
#error "Eigen is configured unlike qdmeta: link the CMake target qdmeta::qdmeta (it defines Eigen's settings), or define EIGEN_MAX_ALIGN_BYTES=16 EIGEN_MAX_STATIC_ALIGN_BYTES=16 EIGEN_MALLOC_ALREADY_ALIGNED=0 for the whole program (qdmeta/core/eigen.hpp)"
#endif
