#pragma once
// a * b + c, fused into one rounding where the CPU has FMA, and left as two where it has none.
//
// Written out rather than left to the compiler's contraction: GCC fuses a vectorised loop's
// body and its scalar remainder differently, so a value would depend on where its batch happened
// to be split (a row's Rastrigin fitness differed between a thread run and an MPI run on an
// AVX-512 CPU), and a file compiled with -ffp-contract=off (CMA-ES, the Rastrigin meta-fitness)
// would round an inline formula differently from one compiled without it.
#include <cmath>

namespace qdmeta {

inline float fused(float a, float b, float c) {
#if defined(__FMA__)
  return std::fma(a, b, c);
#else
  return a * b + c;  // no FMA instruction: nothing can be fused anywhere
#endif
}

inline double fused(double a, double b, double c) {
#if defined(__FMA__)
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

}  // namespace qdmeta
