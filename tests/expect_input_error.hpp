#pragma once
// Shared test helpers for InputError: EXPECT_INPUT_ERROR (`statement` must throw it with exactly
// `message`) and input_error_message (the message a callable throws, to match a part of it).
#include <gtest/gtest.h>

#include <string>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

// The message of the InputError `f()` throws, or "(no InputError)" when it throws none.
inline std::string input_error_message(auto&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace qdmeta

#define EXPECT_INPUT_ERROR(statement, message)                          \
  do {                                                                  \
    try {                                                               \
      statement;                                                        \
      ADD_FAILURE() << "no InputError from " #statement;                \
    } catch (const ::qdmeta::InputError& error) {                       \
      EXPECT_EQ(std::string(error.what()), std::string(message));       \
    }                                                                   \
  } while (false)
