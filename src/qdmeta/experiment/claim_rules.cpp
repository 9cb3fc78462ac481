#include "qdmeta/experiment/claim_rules.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string_view>

#include "qdmeta/core/error.hpp"
#include "qdmeta/run/run_tables.hpp"

namespace qdmeta {

namespace {

using Names = std::vector<std::string>;

const Names kKinds = {"near", "below", "between", "order", "ratio", "top"};
const Names kCommonKeys = {"text", "kind", "measure"};
// Each kind's keys beyond the common ones; every kind may also have `source`.
struct KindKeys {
  Names required, optional;
};
const std::map<std::string, KindKeys, std::less<>> kKindKeys = {
    {"near", {{"conditions", "value", "tolerance"}, {"budget"}}},
    {"below", {{"conditions", "value"}, {"tolerance", "budget"}}},
    {"between", {{"conditions", "low", "high"}, {"budget"}}},
    {"order", {{"groups"}, {}}},
    {"ratio", {{"numerator", "denominator", "value", "tolerance"}, {"budget"}}},
    {"top", {{"conditions", "top"}, {}}},
};
// Whose claim it is: the paper's (the default) or a check of our own, reported apart.
const Names kSources = {"paper", "ours"};
const Names kFamilies = {"final", "population", "meta", "test", "generalisation"};
const Names kPopulationStats = {"num_elites", "obj_mean", "obj_max", "qd_score"};
// summary.json's keys that hold text, not a number a claim could measure.
const Names kSummaryTextKeys = {"algorithm", "task", "stop_reason", "message", "budget_counts",
                                "config_fingerprint"};
constexpr std::string_view kGeneralisation = "generalisation";

bool contains(const Names& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Whether names[i] is also one of names[0..i).
bool repeats(const Names& names, std::size_t i) {
  return std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(i), names[i]) !=
         names.begin() + static_cast<std::ptrdiff_t>(i);
}

// One claim, the file it is in and its place, for the one-line messages.
class ClaimReader {
 public:
  ClaimReader(const toml::table& claim, const std::string& file, std::size_t index)
      : claim_(claim), file_(file), index_(index) {}

  [[noreturn]] void fail(const std::string& rule, const toml::node* at = nullptr) const {
    const toml::source_position p = (at ? at : &claim_)->source().begin;
    const std::string where = p.line ? fmt::format("{}:{}:{}", file_, p.line, p.column) : file_;
    throw InputError(fmt::format("{}: [[claim]] {}: {}", where, index_, rule));
  }

  const toml::node* get(std::string_view key) const { return claim_.get(key); }

  bool is_number(const toml::node* n) const {
    if (n->is_integer()) return true;
    return n->is_floating_point() && std::isfinite(n->as_floating_point()->get());
  }

  // The value of a node is_number accepts.
  double number(const toml::node* n) const {
    return n->is_integer() ? static_cast<double>(n->as_integer()->get()) : n->as_floating_point()->get();
  }

  // A non-empty list of strings.
  Names names(std::string_view key) const {
    const toml::node* node = get(key);
    const toml::array* list = node->as_array();
    Names out;
    if (list)
      for (const toml::node& item : *list)
        if (item.is_string()) out.push_back(item.as_string()->get());
    if (!list || list->empty() || out.size() != list->size())
      fail(fmt::format("{} must be a non-empty list of condition names", key), node);
    return out;
  }

  const toml::table& claim_;
  const std::string& file_;
  std::size_t index_;
};

void check_measure(const ClaimReader& c, const std::string& measure, const Names& tests, const toml::node* at) {
  const std::size_t colon = measure.find(':');
  const std::string family = measure.substr(0, colon);
  const std::string name = colon == std::string::npos ? "" : measure.substr(colon + 1);
  if (colon == std::string::npos || !contains(kFamilies, family) || name.empty())
    c.fail(fmt::format("unknown measure '{}' (families: {})", measure, fmt::join(kFamilies, ", ")), at);
  if (family == "population" && !contains(kPopulationStats, name))
    c.fail(fmt::format("unknown measure '{}' (population: {})", measure, fmt::join(kPopulationStats, ", ")), at);
  if (family == "meta" && !contains(meta_columns(), name))
    c.fail(fmt::format("unknown measure '{}' (meta: a column of meta.csv: {})", measure, fmt::join(meta_columns(), ", ")),
           at);
  if (family == "final") {
    const bool key_name = std::all_of(name.begin(), name.end(), [](char ch) {
      return (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_';
    });
    if (!key_name || contains(kSummaryTextKeys, name))
      c.fail(fmt::format("unknown measure '{}' (final: a numeric key of summary.json)", measure), at);
  }
  if (family == "test") {
    // test:<test>@<evaluations>: one '@', evaluations a positive integer of at most 18 digits.
    const std::size_t sign = name.find('@');
    const std::string test = name.substr(0, sign);
    const std::string at_evals = sign == std::string::npos ? "" : name.substr(sign + 1);
    const bool point = sign != std::string::npos && sign > 0 && !at_evals.empty() && at_evals.size() <= 18 &&
                       at_evals[0] != '0' && at_evals.find_first_not_of("0123456789") == std::string::npos;
    if (!point)
      c.fail(fmt::format("measure '{}' must be test:<test>@<evaluations>, evaluations at least 1", measure), at);
    if (test == kGeneralisation || !contains(tests, test)) {
      Names curves;
      for (const std::string& t : tests)
        if (t != kGeneralisation) curves.push_back(t);
      c.fail(fmt::format("measure '{}' names test '{}', which the experiment does not run (tests: {})", measure, test,
                         curves.empty() ? std::string("none") : fmt::format("{}", fmt::join(curves, ", "))),
             at);
    }
  }
  if (family == "generalisation" && !contains(tests, kGeneralisation))
    c.fail(fmt::format("measure '{}' needs '{}' in the experiment's tests", measure, kGeneralisation), at);
}

void check_names(const ClaimReader& c, const Names& named, const Names& conditions, const toml::node* at) {
  for (std::size_t i = 0; i < named.size(); ++i) {
    if (!contains(conditions, named[i]))
      c.fail(fmt::format("unknown condition '{}' (conditions: {})", named[i], fmt::join(conditions, ", ")), at);
    if (repeats(named, i)) c.fail(fmt::format("condition '{}' is named twice", named[i]), at);
  }
}

// The condition names a claim is about (conditions; numerator and denominator; groups).
Names named_conditions(const ClaimReader& c, const std::string& kind) {
  if (kind == "near" || kind == "below" || kind == "between" || kind == "top") return c.names("conditions");
  if (kind == "ratio") {
    const toml::node* numerator = c.get("numerator");
    if (!numerator->is_string()) c.fail("numerator must be a condition name", numerator);
    Names out{numerator->as_string()->get()};
    for (std::string& n : c.names("denominator")) out.push_back(std::move(n));
    return out;
  }
  const toml::node* groups = c.get("groups");
  const toml::array* list = groups->as_array();
  Names out;
  bool ok = list && list->size() >= 2;
  if (ok)
    for (const toml::node& g : *list) {
      const toml::array* members = g.as_array();
      ok = ok && members && !members->empty();
      if (!ok) break;
      for (const toml::node& m : *members) {
        ok = ok && m.is_string();
        if (ok) out.push_back(m.as_string()->get());
      }
    }
  if (!ok) c.fail("groups must be a list of at least 2 non-empty lists of condition names", groups);
  return out;
}

void check_values(const ClaimReader& c, const std::string& kind, const Names& named) {
  const toml::node* value = c.get("value");
  if ((kind == "near" || kind == "below") && value->is_table()) {
    const toml::table& table = *value->as_table();
    for (const auto& [name, v] : table) {
      if (!contains(named, name.str()))
        c.fail(fmt::format("value names '{}', which is not one of the claim's conditions", name.str()), &v);
      if (!c.is_number(&v)) c.fail(fmt::format("value for '{}' must be a finite number", name.str()), &v);
    }
    for (const std::string& name : named)
      if (!table.contains(name)) c.fail(fmt::format("value has no number for condition '{}'", name), value);
  } else if (kind == "near" || kind == "below" || kind == "ratio") {
    if (!c.is_number(value)) c.fail("value must be a finite number", value);
  }
  if (kind == "between") {
    const toml::node* low = c.get("low");
    const toml::node* high = c.get("high");
    if (!c.is_number(low)) c.fail("low must be a finite number", low);
    if (!c.is_number(high)) c.fail("high must be a finite number", high);
    if (!(c.number(low) < c.number(high))) c.fail("low must be below high", low);
  }
  if (const toml::node* t = c.get("tolerance")) {
    if (!c.is_number(t) || c.number(t) < 0) c.fail("tolerance must be a finite number of at least 0", t);
  }
  if (const toml::node* b = c.get("budget")) {
    if (!b->is_integer() || b->as_integer()->get() < 1) c.fail("budget must be an integer of at least 1", b);
  }
  if (const toml::node* s = c.get("source")) {
    if (!s->is_string() || !contains(kSources, s->as_string()->get()))
      c.fail(fmt::format("source must be one of {}", fmt::join(kSources, ", ")), s);
  }
}

void check_claim(const ClaimReader& c, const Names& conditions, const Names& tests) {
  const toml::node* kind_node = c.get("kind");
  if (!kind_node) c.fail("missing key 'kind'");
  if (!kind_node->is_string()) c.fail("kind must be a string", kind_node);
  const std::string kind = kind_node->as_string()->get();
  if (!contains(kKinds, kind))
    c.fail(fmt::format("unknown kind '{}' (kinds: {})", kind, fmt::join(kKinds, ", ")), kind_node);
  const KindKeys& keys = kKindKeys.find(kind)->second;
  Names valid = kCommonKeys, needed = kCommonKeys;
  valid.insert(valid.end(), keys.required.begin(), keys.required.end());
  valid.insert(valid.end(), keys.optional.begin(), keys.optional.end());
  valid.push_back("source");
  needed.insert(needed.end(), keys.required.begin(), keys.required.end());
  for (const auto& [key, node] : c.claim_)
    if (!contains(valid, key.str()))
      c.fail(fmt::format("unknown key '{}' for kind '{}' (valid keys: {})", key.str(), kind, fmt::join(valid, ", ")),
             &node);
  for (const std::string& key : needed)
    if (!c.get(key))
      c.fail(fmt::format("missing key '{}' (kind '{}' needs {})", key, kind, fmt::join(needed, ", ")));

  const toml::node* text = c.get("text");
  const std::string_view words = text->is_string() ? std::string_view(text->as_string()->get()) : std::string_view();
  if (words.find_first_not_of(" \t\r\n\v\f") == std::string_view::npos || words.find('\n') != std::string_view::npos ||
      words.find('|') != std::string_view::npos)
    c.fail("text must be a non-empty string on one line without '|'", text);

  const toml::node* measure = c.get("measure");
  Names measures;
  if (measure->is_string()) {
    measures.push_back(measure->as_string()->get());
  } else if (const toml::array* list = measure->as_array()) {
    for (const toml::node& m : *list)
      if (m.is_string()) measures.push_back(m.as_string()->get());
    if (list->empty() || measures.size() != list->size()) measures.clear();
  }
  if (measures.empty()) c.fail("measure must be a string or a non-empty list of strings", measure);
  for (std::size_t i = 0; i < measures.size(); ++i) {
    if (repeats(measures, i)) c.fail(fmt::format("measure '{}' is listed twice", measures[i]), measure);
    check_measure(c, measures[i], tests, measure);
  }

  const Names named = named_conditions(c, kind);
  check_names(c, named, conditions, kind == "ratio" ? nullptr : c.get(kind == "order" ? "groups" : "conditions"));
  if (kind == "top") {
    const toml::node* top = c.get("top");
    if (!top->is_string() || !contains(named, top->as_string()->get()))
      c.fail("top must be one of the claim's conditions", top);
  }
  check_values(c, kind, named);
}

}  // namespace

void check_claims(const toml::array& claims, const std::vector<std::string>& conditions,
                  const std::vector<std::string>& tests, const std::string& file) {
  std::size_t index = 0;
  for (const toml::node& node : claims) {
    ++index;
    const toml::table* claim = node.as_table();
    if (!claim) throw InputError(fmt::format("{}: [[claim]] {}: must be a table", file, index));
    check_claim(ClaimReader(*claim, file, index), conditions, tests);
  }
}

}  // namespace qdmeta
