// Tests of src/qdmeta/archive/elite_checks.{hpp,cpp}: the value check of a restored archive
// (checkpoints and pickles share it).
#include "qdmeta/archive/elite_checks.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "expect_input_error.hpp"

namespace qdmeta {
namespace {

// Whether checking `t` throws an InputError whose message holds `part`.
::testing::AssertionResult refused_with(const EliteTable& t, const std::string& what, const std::string& part) {
  const std::string message = input_error_message([&] { check_restored_elites(t, what); });
  if (message.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "message: " << message;
}

EliteTable two_elites() {
  EliteTable t;
  t.index = {4, 9};
  t.objective = {-1.0f, -2.0f};
  t.measures = RowMatrix::Constant(2, 2, 0.5f);
  t.solutions = RowMatrix::Constant(2, 3, 0.25f);
  t.base_features = RowMatrix::Constant(2, 2, 0.0f);
  return t;
}

TEST(EliteChecks, TheBoundsThemselvesAreAccepted) {
  EliteTable t = two_elites();
  t.solutions(0, 0) = 0.0f;
  t.solutions(1, 2) = 1.0f;
  t.base_features(0, 1) = -1.0f;  // 2g - 1 of a gene 0
  t.base_features(1, 0) = 1.0f;
  EXPECT_NO_THROW(check_restored_elites(t, "state"));
  EXPECT_NO_THROW(check_restored_elites(EliteTable{}, "state"));
}

TEST(EliteChecks, AGeneOutsideTheUnitIntervalOrNanIsRefusedNamingTheElite) {
  EliteTable t = two_elites();
  t.solutions(1, 2) = 1.5f;
  EXPECT_TRUE(refused_with(t, "run/checkpoint.bin",
                           "run/checkpoint.bin is damaged: elite 1 (cell 9) has a gene 1.5, where every gene must "
                           "lie in [0, 1]"));
  t.solutions(1, 2) = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_TRUE(refused_with(t, "state", "has a gene nan, where every gene must lie in [0, 1]"));
  t = two_elites();
  t.solutions(0, 0) = -1e-9f;
  EXPECT_TRUE(refused_with(t, "state", "elite 0 (cell 4) has a gene -1e-09"));
}

TEST(EliteChecks, AStoredBaseFeatureOutsideMinusOneToOneIsRefused) {
  EliteTable t = two_elites();
  t.base_features(0, 1) = -1.5f;
  EXPECT_TRUE(refused_with(t, "state",
                           "elite 0 (cell 4) has a base feature -1.5, where every stored base feature must lie in "
                           "[-1, 1]"));
}

}  // namespace
}  // namespace qdmeta
