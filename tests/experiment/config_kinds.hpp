#pragma once
// Every kind of run a config can describe, and the key log (plugin/config.hpp) of reading them
// all: what docs/config.md and the parameter descriptors are checked against.
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/plugin/config.hpp"
#ifdef QDMETA_TEST_RHEX
#include "qdmeta/tasks/rhex/rhex_config.hpp"
#endif

namespace qdmeta {

// Every kind of run a config can describe: each algorithm with each of its alternatives.
inline std::vector<std::string> every_kind_of_config() {
  std::vector<std::string> tasks = {"rastrigin"};
#ifdef QDMETA_TEST_RHEX
  tasks.push_back("rhex");
#endif
  std::vector<std::string> configs;
  for (const std::string& task : tasks) {
    const std::string head = "[task]\nname = \"" + task + "\"\n";
    for (const char* mutation : {"gaussian", "discrete-step", "uniform-resample", "iso-line"})
      configs.push_back(head + "[mutation]\nkind = \"" + mutation + "\"\n");
    configs.push_back("algorithm = \"map-elites\"\n" + head);
    for (const char* points : {"uniform", "random-descriptors"})
      configs.push_back("algorithm = \"cvt-map-elites\"\n" + head + "[cvt]\npoints = \"" + points + "\"\ncache = false\n");
    // Keys read only where written (so older runs' resolved configs stay as they were).
    configs.push_back("algorithm = \"cvt-map-elites\"\n" + head + "[cvt]\ncache = false\ncentroids_file = \"unread.dat\"\n");
    configs.push_back("algorithm = \"qd-meta\"\n" + head + "[qd_meta]\ndatabase_inputs = \"authors-2g-1\"\n[cma_es]\nsmall_population = \"authors\"\n");
    configs.push_back("algorithm = \"qd-meta\"\n" + head + "[qd_meta]\nbottom_level = \"cma-mae\"\n[emitters]\nadd_mode = \"batch\"\n");
    configs.push_back("algorithm = \"aurora\"\n" + head);
    for (const char* emitters : {"cma-me", "cma-mae"}) {
      configs.push_back("algorithm = \"" + std::string(emitters) + "\"\n" + head);
      configs.push_back("algorithm = \"" + std::string(emitters) + "\"\n" + head +
                        "[emitters]\nrestart_rule = \"every-n\"\n[archive]\nkind = \"cvt\"\n[cvt]\ncache = false\n");
    }
    for (const char* kind : {"gaussian", "iso-line"})
      configs.push_back("algorithm = \"cma-me\"\n" + head + "[emitters]\nkind = \"" + kind + "\"\n");
    configs.push_back("algorithm = \"cma-mae\"\n" + head + "[emitters]\nkind = \"evolution-strategy\"\nes = \"sep-cma-es\"\n");
    const std::vector<std::string> metas =
        task == "rastrigin" ? std::vector<std::string>{"translation", "dimension"} : std::vector<std::string>{"damage", "obstacle"};
    for (const std::string& meta : metas)
      for (const char* control : {"sarsa", "static"})
        configs.push_back("algorithm = \"qd-meta\"\n" + head + "[meta_fitness]\nkind = \"" + meta + "\"\n[control]\nkind = \"" +
                          control + "\"\n");
  }
  return configs;
}

inline std::vector<ConfigKeyRecord> keys_the_code_reads() {
#ifdef QDMETA_TEST_RHEX
  register_rhex_task();
#endif
  std::vector<ConfigKeyRecord> log;
  {
    const ScopedConfigKeyLog recording(log);
    for (const std::string& text : every_kind_of_config()) {
      const toml::table config = toml::parse(text);
      build_run(config, "generated", {}, BuildScope::kTasksOnly);
    }
  }
  // QDMETA_DUMP_CONFIG_KEYS=FILE: the log as TSV, to update the reference from.
  if (const char* dump = std::getenv("QDMETA_DUMP_CONFIG_KEYS")) {
    std::ofstream out(dump);
    for (const auto& r : log) out << r.key << '\t' << r.type << '\t' << r.fallback << '\t' << r.range << '\n';
  }
  return log;
}

}  // namespace qdmeta
