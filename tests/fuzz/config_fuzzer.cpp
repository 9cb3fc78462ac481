#include "config_fuzzer.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <toml++/toml.h>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/plugin/toml_text.hpp"

namespace qdmeta::fuzz {
namespace {

// Values a careless or hostile config might hold for any key.

void replace_with_extreme(toml::table& t, const std::string& key, std::mt19937_64& rng) {
  switch (rng() % 22) {
    case 0: t.insert_or_assign(key, 0); break;
    case 1: t.insert_or_assign(key, -1); break;
    case 2: t.insert_or_assign(key, std::int64_t{1} << 31); break;
    case 3: t.insert_or_assign(key, std::numeric_limits<std::int64_t>::max()); break;
    case 4: t.insert_or_assign(key, std::numeric_limits<std::int64_t>::min()); break;
    case 5: t.insert_or_assign(key, 1e300); break;
    case 6: t.insert_or_assign(key, -1e300); break;
    case 7: t.insert_or_assign(key, std::numeric_limits<double>::quiet_NaN()); break;
    case 8: t.insert_or_assign(key, std::numeric_limits<double>::infinity()); break;
    case 9: t.insert_or_assign(key, 0.5); break;
    case 10: t.insert_or_assign(key, 1e-300); break;
    case 11: t.insert_or_assign(key, ""); break;
    case 12: t.insert_or_assign(key, "no-such-choice"); break;
    case 13: t.insert_or_assign(key, true); break;
    case 14: t.insert_or_assign(key, toml::array{}); break;
    case 15: t.insert_or_assign(key, toml::array{0}); break;
    case 16: t.insert_or_assign(key, toml::array{1'000'000'000, 1'000'000'000}); break;
    case 17: t.insert_or_assign(key, toml::table{}); break;
    case 18: t.insert_or_assign(key, static_cast<std::int64_t>(rng() % 2000) - 1000); break;
    case 19: t.insert_or_assign(key, static_cast<std::int64_t>(std::pow(10.0, static_cast<double>(rng() % 13)))); break;
    case 20: t.insert_or_assign(key, std::ldexp(1.0, static_cast<int>(rng() % 80) - 40)); break;
    default: {
      toml::array a;
      for (int i = 0, n = static_cast<int>(rng() % 20); i < n; ++i) a.push_back(static_cast<std::int64_t>(rng() % 300) - 5);
      t.insert_or_assign(key, std::move(a));
    }
  }
}

// Every table of the config, the root included, so a mutation can pick one.
void tables_of(toml::table& t, std::vector<toml::table*>& out) {
  out.push_back(&t);
  for (auto&& [k, v] : t)
    if (auto* sub = v.as_table()) tables_of(*sub, out);
}

// Known table and key names, so that mutations often hit keys that exist in some other table.
const std::vector<std::string>& names() {
  static const std::vector<std::string> n = {
      "algorithm", "seed",      "budget",     "evaluations", "task",       "name",      "dimensions", "mutation",
      "kind",      "sigma",     "step",       "rate",        "archive",    "bins",      "lower",      "upper",
      "measures",  "qd_meta",   "hidden",     "batch_size",  "control",    "generations", "max_generations",
      "cvt",       "centroids", "samples",    "aurora",      "latent_size", "target_size", "meta_fitness",
      "dimensions", "checkpoint", "every_seconds", "map_elites", "initial_population", "database_capacity",
      "meta_population", "cma_es", "bounds", "cache", "unknown_key"};
  return n;
}

std::string mutate_structure(const std::string& text, std::mt19937_64& rng) {
  toml::table t = toml::parse(text);
  for (int m = 0, count = 1 + static_cast<int>(rng() % 4); m < count; ++m) {
    std::vector<toml::table*> tables;
    tables_of(t, tables);
    toml::table& target = *tables[rng() % tables.size()];
    std::vector<std::string> keys;
    for (auto&& [k, v] : target) keys.emplace_back(k.str());
    const std::string& name = names()[rng() % names().size()];
    switch (rng() % 4) {
      case 0:  // drop a key
        if (!keys.empty()) target.erase(keys[rng() % keys.size()]);
        break;
      case 1:  // change an existing value
        if (!keys.empty()) replace_with_extreme(target, keys[rng() % keys.size()], rng);
        break;
      case 2:  // add a key (often one that is valid elsewhere)
        replace_with_extreme(target, name, rng);
        break;
      default:  // switch the algorithm or the task
        t.insert_or_assign("algorithm", std::string(std::vector<const char*>{"map-elites", "qd-meta", "cvt-map-elites",
                                                                             "aurora"}[rng() % 4]));
    }
  }
  std::ostringstream out;
  out << t;
  return out.str();
}

// What toml++ alone would not refuse safely: a NUL byte (it stops reading there), table headers,
// dotted keys and values nested thousands deep (its recursion exhausts the stack).
std::string mutate_hostile(std::string text, std::mt19937_64& rng) {
  const int depth = std::vector<int>{31, 32, 33, 100, 1'000, 100'000}[rng() % 6];
  const auto repeat = [&](const std::string& first, const std::string& next) {
    std::string s = first;
    for (int i = 1; i < depth; ++i) s += next;
    return s;
  };
  const std::size_t at = text.empty() ? 0 : rng() % text.size();
  switch (rng() % 6) {
    case 0: text.insert(at, 1, '\0'); break;
    case 1: text += "\n[" + repeat("a", ".a") + "]\nx = 1\n"; break;
    case 2: text += "\n[[" + repeat("a", " . a") + "]]\n"; break;
    case 3: text = repeat("a", ".\"a\"") + " = 1\n" + text; break;
    case 4: text = "x = " + repeat("[", "[") + std::string(static_cast<std::size_t>(depth), ']') + "\n" + text; break;
    default: text = "x = " + repeat("{a=", "{a=") + "1" + std::string(static_cast<std::size_t>(depth), '}') + "\n" + text;
  }
  return text;
}

std::string mutate_bytes(std::string text, std::mt19937_64& rng) {
  static const std::string alphabet = "[]{}=\"'.,#\n 0123456789e+-_abcxyz\\";
  for (int m = 0, count = 1 + static_cast<int>(rng() % 3); m < count && !text.empty(); ++m) {
    const std::size_t at = rng() % text.size();
    switch (rng() % 3) {
      case 0: text[at] = alphabet[rng() % alphabet.size()]; break;
      case 1: text.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
      default: text.erase(at, 1);
    }
  }
  return text;
}

}  // namespace

std::vector<std::string> seed_configs(const std::string& configs_dir) {
  std::vector<std::string> texts;
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(configs_dir))
    if (e.is_regular_file() && e.path().extension() == ".toml" && !e.path().filename().string().starts_with("experiment"))
      files.push_back(e.path());
  std::sort(files.begin(), files.end());  // a fixed order: cases reproduce from the seed
  for (const auto& f : files) {
    std::ifstream in(f);
    std::stringstream s;
    s << in.rdbuf();
    texts.push_back(s.str());
  }
  return texts;
}

FuzzReport fuzz_configs(const std::vector<std::string>& seeds, std::uint64_t seed, int cases) {
  FuzzReport report;
  using Clock = std::chrono::steady_clock;
  for (int i = 0; i < cases; ++i) {
    std::mt19937_64 rng(seed * 1'000'003 + static_cast<std::uint64_t>(i));
    const std::string& base = seeds[rng() % seeds.size()];
    std::string text;
    try {
      const auto kind = rng() % 8;
      text = kind < 2 ? mutate_bytes(base, rng) : kind == 2 ? mutate_hostile(base, rng) : mutate_structure(base, rng);
    } catch (const toml::parse_error&) {
      text = mutate_bytes(base, rng);
    }
    ++report.cases;
    const auto start = Clock::now();
    try {
      const toml::table config = parse_toml_text(text, "generated");
      const BuiltRun tasks = build_run(config, "generated", {}, BuildScope::kTasksOnly);
      // Allocate only what is small: the estimate guards the rest (and is what is tested here).
      if (tasks.memory.total() < 32.0 * 1024 * 1024) {
        const BuiltRun run = build_run(config, "generated", {}, BuildScope::kRun);
        report.built_algorithms += run.algorithm != nullptr;
      }
      ++report.accepted;
    } catch (const InputError&) {
      ++report.refused;
    } catch (const std::bad_alloc&) {
      report.defects.push_back(text + "\n=> bare std::bad_alloc");
    } catch (const std::exception& e) {
      report.defects.push_back(text + "\n=> " + typeid(e).name() + ": " + e.what());
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (seconds > report.slowest_seconds) {
      report.slowest_seconds = seconds;
      report.slowest_case = text;
    }
  }
  return report;
}

}  // namespace qdmeta::fuzz
