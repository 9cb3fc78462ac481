// Tests of src/qdmeta/plugin/registry.hpp, the one registry type behind tasks, their
// meta-objective kinds and algorithms: registration order, replacement in place, snapshots that
// outlive replacement and removal, copy-on-write updates, and names a build lacks.
#include "qdmeta/plugin/registry.hpp"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

namespace qdmeta {
namespace {

using NameList = std::vector<std::string>;

TEST(Registry, KeepsRegistrationOrderAndReplacesInPlace) {
  Registry<int> r;
  EXPECT_TRUE(r.names().empty());
  r.add("b", 1);
  r.add("a", 2);
  r.add("c", 3);
  r.add("b", 10);  // replaced, keeps its place
  EXPECT_EQ(r.names(), (NameList{"b", "a", "c"}));
  EXPECT_EQ(*r.find("b"), 10);
  EXPECT_EQ(r.find("d"), nullptr);
  EXPECT_TRUE(r.contains("a"));
  EXPECT_FALSE(r.contains("d"));
}

TEST(Registry, AFoundPluginIsASnapshot) {
  Registry<std::string> r;
  r.add("x", "first");
  const auto held = r.find("x");
  r.add("x", "second");
  EXPECT_EQ(*held, "first");
  EXPECT_EQ(*r.find("x"), "second");
  EXPECT_TRUE(r.remove("x"));
  EXPECT_FALSE(r.remove("x"));
  EXPECT_EQ(r.find("x"), nullptr);
  EXPECT_EQ(*held, "first");
}

TEST(Registry, UpdateEditsACopyAndSwapsItInOnlyWhenSomethingChanged) {
  Registry<NameList> r;
  r.add("t", NameList{"k1"});
  const auto before = r.find("t");
  EXPECT_TRUE(r.update("t", [](NameList& kinds) {
    kinds.push_back("k2");
    return true;
  }));
  EXPECT_EQ(*before, NameList{"k1"});
  EXPECT_EQ(*r.find("t"), (NameList{"k1", "k2"}));
  const auto after = r.find("t");
  EXPECT_FALSE(r.update("t", [](NameList& kinds) {
    kinds.clear();  // a change the edit disowns: not applied
    return false;
  }));
  EXPECT_EQ(r.find("t").get(), after.get());
  EXPECT_FALSE(r.update("absent", [](NameList&) { return true; }));
  EXPECT_EQ(r.names(), NameList{"t"});
}

TEST(Registry, UnavailableNamesGiveWayToARegisteredPlugin) {
  Registry<int> r;
  r.add_unavailable("rhex", "needs DART");
  r.add_unavailable("other", "needs X");
  EXPECT_EQ(r.unavailable_names(), (NameList{"other", "rhex"}));
  EXPECT_EQ(r.why_unavailable("rhex"), "needs DART");
  EXPECT_EQ(r.why_unavailable("nothing"), "");
  r.add("rhex", 1);
  EXPECT_EQ(r.unavailable_names(), NameList{"other"});
  EXPECT_TRUE(r.names() == NameList{"rhex"});
}

// Registrations and lookups from several threads at once leave every name registered once.
TEST(Registry, ConcurrentRegistrationsAreAllKept) {
  Registry<int> r;
  NameList names;
  for (int i = 0; i < 50; ++i) names.push_back(std::string("n").append(std::to_string(i)));
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&r, &names, t] {
      for (std::size_t i = 0; i < 200; ++i) {
        r.add(names[i % 50], t);
        (void)r.find(names[(i * 7) % 50]);
      }
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(r.names().size(), 50u);
}

TEST(QuotedNames, ListsAsTheConfigMessagesDo) {
  EXPECT_EQ(quoted_names({}), "");
  EXPECT_EQ(quoted_names({"a"}), "\"a\"");
  EXPECT_EQ(quoted_names({"a", "b-c"}), "\"a\", \"b-c\"");
}

}  // namespace
}  // namespace qdmeta
