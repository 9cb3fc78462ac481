#pragma once
// Shared test helpers for MutationParams: the operators' parameter sets the tests build, and
// the message validate() refuses a set with.
#include <string>

#include "expect_input_error.hpp"
#include "qdmeta/core/mutation.hpp"

namespace qdmeta {

inline MutationParams gaussian(double rate, double sigma = 0.05) {
  MutationParams p;
  p.kind = MutationKind::kGaussian;
  p.rate = rate;
  p.sigma = sigma;
  return p;
}

inline MutationParams iso_line(double iso_sigma = 0.01, double line_sigma = 0.2) {
  MutationParams p;
  p.kind = MutationKind::kIsoLine;
  p.iso_sigma = iso_sigma;
  p.line_sigma = line_sigma;
  return p;
}

inline std::string message_of(const MutationParams& p) {
  return input_error_message([&] { p.validate(); });
}

}  // namespace qdmeta
