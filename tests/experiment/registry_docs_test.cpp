// The documentation against the registries: docs/config.md lists exactly the algorithms, tasks
// and meta-objective kinds that are registered, and every code block of the tutorials
// (docs/library.md, docs/tutorials/*.md) is the example's code, verbatim, so neither can rot.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/cli/builtin_plugins.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"
#include "qdmeta/plugin/task_registry.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The quoted names in the range column (the fourth) of the key row `key` under the section
// whose heading contains `section`, up to a ';' (which starts prose).
std::vector<std::string> documented_choices(const std::string& section, const std::string& key) {
  bool in_section = false;
  for (const std::string& line : lines_of(slurp(fs::path(QDMETA_SOURCE_DIR) / "docs" / "config.md"))) {
    if (line.starts_with("## ")) in_section = line.find(section) != std::string::npos;
    if (!in_section || !line.starts_with("| `" + key + "` |")) continue;
    std::vector<std::string> cells;
    std::stringstream row(line.substr(1));
    for (std::string cell; std::getline(row, cell, '|');) cells.push_back(cell);
    std::string range = cells.at(3);
    range = range.substr(0, range.find(';'));
    std::vector<std::string> names;
    const std::regex quoted("\"([^\"]+)\"");
    for (auto it = std::sregex_iterator(range.begin(), range.end(), quoted); it != std::sregex_iterator(); ++it)
      names.push_back((*it)[1]);
    return names;
  }
  ADD_FAILURE() << "docs/config.md has no row `" << key << "` under a heading with " << section;
  return {};
}

// The plugins the qdmeta executable registers (RHex when this test links it).
class RegistryDocs : public ::testing::Test {
 protected:
  void SetUp() override { register_builtin_plugins(); }
};

std::vector<std::string> sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  return v;
}

TEST_F(RegistryDocs, ConfigMdListsTheRegisteredAlgorithmsInOrder) {
  EXPECT_EQ(documented_choices("Top level", "algorithm"), registered_algorithm_names());
  EXPECT_EQ(registered_algorithm_names().front(), "map-elites");  // the default
}

TEST_F(RegistryDocs, ConfigMdListsTheRegisteredTasksAndThoseThisBuildLacks) {
  std::vector<std::string> expected = registered_task_names();
  for (const auto& name : unavailable_task_names()) expected.push_back(name);
  EXPECT_EQ(sorted(documented_choices("`[task]`", "name")), sorted(expected));
  EXPECT_NE(std::find(expected.begin(), expected.end(), "rastrigin"), expected.end());
}

TEST_F(RegistryDocs, ConfigMdListsEachTasksMetaObjectives) {
  for (const std::string& task : registered_task_names()) {
    const auto plugin = find_task_plugin(task);
    ASSERT_NE(plugin, nullptr);
    std::vector<std::string> kinds;
    for (const auto& [kind, reader] : plugin->meta_objectives) kinds.push_back(kind);
    EXPECT_EQ(sorted(documented_choices("task `\"" + task + "\"`", "kind")), sorted(kinds)) << task;
  }
}

TEST_F(RegistryDocs, AnUnknownTaskListsTheRegisteredOnesAndSaysWhyRhexIsMissing) {
  if (find_task_plugin("rhex") != nullptr) GTEST_SKIP() << "built with the RHex task";
  toml::table config = toml::parse("[task]\nname = \"rhex\"\n");
  try {
    build_run(config, "x.toml", {}, BuildScope::kTasksOnly);
    FAIL() << "task rhex was accepted by a build without it";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "x.toml: task.name = \"rhex\" is not a valid choice: use one of \"rastrigin\" "
                                     "(this build has no RHex task: it needs DART)");
  }
}

TEST_F(RegistryDocs, ARegisteredTaskIsBuiltAndListed) {
  TaskPlugin plugin = *find_task_plugin("rastrigin");
  register_task_plugin("rastrigin-copy", plugin);
  const BuiltRun built =
      build_run(toml::parse("[task]\nname = \"rastrigin-copy\"\ndimensions = 3\n"), "x.toml", {}, BuildScope::kTasksOnly);
  EXPECT_EQ(built.evaluation_tasks.front().genotype_size(), 3);
  const auto names = registered_task_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "rastrigin-copy"), names.end());
  EXPECT_NE(describe_adaptation_tests().find("rastrigin-copy: dimension, translation"), std::string::npos);
}

// A found plugin or builder is a snapshot: registering again under its name (or adding a
// meta-objective to it) replaces what later lookups find, never what a caller holds.
TEST_F(RegistryDocs, ALookupSurvivesReRegistration) {
  TaskPlugin plugin = *find_task_plugin("rastrigin");
  plugin.adaptation_tests = {"first"};
  register_task_plugin("rastrigin-snapshot", plugin);
  const auto held = find_task_plugin("rastrigin-snapshot");
  plugin.adaptation_tests = {"second"};
  register_task_plugin("rastrigin-snapshot", plugin);
  register_meta_objective("rastrigin-snapshot", "added", plugin.meta_objectives.front().second);
  EXPECT_EQ(held->adaptation_tests, std::vector<std::string>{"first"});
  EXPECT_EQ(held->meta_objectives.size(), plugin.meta_objectives.size());
  const auto now = find_task_plugin("rastrigin-snapshot");
  EXPECT_EQ(now->adaptation_tests, std::vector<std::string>{"second"});
  EXPECT_EQ(now->meta_objectives.back().first, "added");

  EXPECT_TRUE(unregister_meta_objective("rastrigin-snapshot", "added"));
  EXPECT_FALSE(unregister_meta_objective("rastrigin-snapshot", "added"));
  EXPECT_EQ(now->meta_objectives.back().first, "added") << "a snapshot outlives an unregistration";
  EXPECT_EQ(find_task_plugin("rastrigin-snapshot")->meta_objectives.size(), plugin.meta_objectives.size());
  EXPECT_TRUE(unregister_task_plugin("rastrigin-snapshot"));
  EXPECT_EQ(find_task_plugin("rastrigin-snapshot"), nullptr);
  EXPECT_FALSE(unregister_task_plugin("rastrigin-snapshot"));
  EXPECT_EQ(now->adaptation_tests, std::vector<std::string>{"second"});

  const auto builder = find_algorithm("map-elites");
  ASSERT_NE(builder, nullptr);
  register_algorithm("map-elites-snapshot", *builder);
  const auto held_builder = find_algorithm("map-elites-snapshot");
  register_algorithm("map-elites-snapshot", [](AlgorithmBuild&) -> AlgorithmMaker { return {}; });
  EXPECT_NE(held_builder.get(), find_algorithm("map-elites-snapshot").get());
  EXPECT_TRUE(static_cast<bool>(*held_builder));
}

// The ```cpp, ```cmake and ```toml blocks of the Markdown file `doc`: how many there are, each
// checked to appear verbatim in `example`.
int expect_blocks_in(const fs::path& doc, const std::string& example) {
  int blocks = 0;
  std::string block, fence;
  for (const std::string& line : lines_of(slurp(doc))) {
    if (fence.empty() && line.starts_with("```") && line.size() > 3) {
      fence = line.substr(3);
      block.clear();
    } else if (!fence.empty() && line == "```") {
      if (fence == "cpp" || fence == "cmake" || fence == "toml") {
        ++blocks;
        EXPECT_NE(example.find(block), std::string::npos) << doc.filename().string() << "'s " << fence
                                                          << " block is not in examples/own-task/:\n" << block;
      }
      fence.clear();
    } else if (!fence.empty()) {
      block += line + "\n";
    }
  }
  return blocks;
}

// Each such block of docs/library.md and of the C++ tutorials in docs/tutorials/ appears,
// verbatim, in one file of examples/own-task/. A Python tutorial (one with ```python blocks and
// none of these) is run by tests/python/test_tutorials.py instead.
TEST(LibraryDocs, EveryCodeBlockIsTheExamplesCode) {
  const fs::path source(QDMETA_SOURCE_DIR);
  std::string example;
  for (const auto& entry : fs::recursive_directory_iterator(source / "examples" / "own-task"))
    if (entry.is_regular_file()) example += slurp(entry.path()) + "\n\x1f\n";  // no block spans two files
  std::vector<fs::path> docs;
  for (const auto& entry : fs::directory_iterator(source / "docs" / "tutorials"))
    if (entry.path().extension() == ".md") {
      const std::string text = slurp(entry.path());
      const bool python_only = text.find("```python") != std::string::npos && text.find("```cpp") == std::string::npos &&
                               text.find("```cmake") == std::string::npos && text.find("```toml") == std::string::npos;
      if (!python_only) docs.push_back(entry.path());
    }
  std::sort(docs.begin(), docs.end());
  EXPECT_GE(docs.size(), 2u);  // mutation-operator.md, algorithm.md
  docs.insert(docs.begin(), source / "docs" / "library.md");
  for (const fs::path& doc : docs) EXPECT_GE(expect_blocks_in(doc, example), 5) << doc;
}

}  // namespace
}  // namespace qdmeta
