#pragma once
// What the run directory tests share: a fresh, empty directory of this test's own (removed
// after it), files written into it, and a summary.json that says why the run stopped.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "own_temp_path.hpp"
#include "qdmeta/run/summary.hpp"

namespace qdmeta::test {

class RunDirFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = own_temp_path(std::string("run_dir_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }
  void write_summary_saying(StopReason reason) const {
    RunResult result;
    result.reason = reason;
    const RunSettings settings;
    write_summary(dir_ / "summary.json", SummaryRecord{result, settings, "map-elites", 1, {}});
  }
  std::filesystem::path dir_;
};

}  // namespace qdmeta::test
