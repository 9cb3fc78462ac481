#include "qdmeta/assembly/config_fingerprint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <sstream>

#include "qdmeta/core/binary_io.hpp"

namespace qdmeta {
namespace {

void collect_differences(const toml::table& a, const toml::table& b, const std::string& prefix,
                         std::vector<std::string>& out) {
  const auto key_of = [&](std::string_view k) { return prefix.empty() ? std::string(k) : prefix + "." + std::string(k); };
  for (const auto& [k, v] : a) {
    const toml::node* other = b.get(k);
    if (other && v.is_table() && other->is_table())
      collect_differences(*v.as_table(), *other->as_table(), key_of(k.str()), out);
    else if (!other || toml::node_view<const toml::node>(&v) != toml::node_view<const toml::node>(other))
      out.push_back(key_of(k.str()));
  }
  for (const auto& [k, v] : b)
    if (!a.contains(k)) out.push_back(key_of(k.str()));
}

}  // namespace

std::uint64_t config_fingerprint(const toml::table& resolved) {
  toml::table copy = resolved;
  copy.erase("provenance");
  std::ostringstream text;
  text << copy;
  return fnv1a64(text.str());
}

toml::table fingerprinted_config(const toml::table& resolved) {
  toml::table t = resolved;
  t.erase("seed");
  t.erase("provenance");
  t.erase("checkpoint");
  if (auto* cvt = t["cvt"].as_table()) {
    cvt->erase("cache");
    cvt->erase("cache_dir");
    if (cvt->empty()) t.erase("cvt");
  }
  return t;
}

std::string resolved_config_fingerprint(const toml::table& resolved) {
  std::ostringstream text;
  text << fingerprinted_config(resolved);
  return fmt::format("{:016x}", fnv1a64(text.str()));
}

bool is_config_fingerprint(const std::string& text) {
  return text.size() == 16 &&
         std::all_of(text.begin(), text.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

std::vector<std::string> differing_keys(const toml::table& a, const toml::table& b) {
  std::vector<std::string> out;
  collect_differences(fingerprinted_config(a), fingerprinted_config(b), "", out);
  std::sort(out.begin(), out.end());
  return out;
}

std::string keys_that_differ(const std::vector<std::string>& keys) {
  constexpr std::size_t kShown = 6;
  if (keys.empty()) return "its resolved config differs";  // the same keys and values, written otherwise
  std::string out;
  for (std::size_t i = 0; i < keys.size() && i < kShown; ++i) out += (i ? ", " : "") + keys[i];
  if (keys.size() > kShown) out += fmt::format(" and {} more", keys.size() - kShown);
  return out + (keys.size() == 1 ? " differs" : " differ");
}

}  // namespace qdmeta
