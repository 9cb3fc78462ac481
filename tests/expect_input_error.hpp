#pragma once
// Shared test assertion: `statement` must throw qdmeta::InputError with exactly `message`.
#include <gtest/gtest.h>

#include <string>

#include "qdmeta/core/error.hpp"

#define EXPECT_INPUT_ERROR(statement, message)                          \
  do {                                                                  \
    try {                                                               \
      statement;                                                        \
      ADD_FAILURE() << "no InputError from " #statement;                \
    } catch (const ::qdmeta::InputError& error) {                       \
      EXPECT_EQ(std::string(error.what()), std::string(message));       \
    }                                                                   \
  } while (false)
