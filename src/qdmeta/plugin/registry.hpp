#pragma once
// The one registry type behind every name a config file chooses: tasks and their meta-objective
// kinds (plugin/task_registry.hpp) and algorithms (plugin/algorithm_registry.hpp). A name
// maps to a plugin value. Lookups return immutable snapshots, so a plugin a caller found stays
// valid and unchanged while others are registered or it is replaced. Names keep the order they
// were first registered in (the order of the CLI's and docs/config.md's lists); a name registered
// again keeps its place. Thread-safe.
//
// A registry knows nothing of the built-in plugins: they register through the same calls as a
// user's (assembly/core_plugins.hpp), so no registry calls back into the code that fills it.
#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace qdmeta {

template <class Plugin>
class Registry {
 public:
  // Registers `plugin` under `name`, replacing a plugin of that name.
  void add(const std::string& name, Plugin plugin) {
    auto owned = std::make_shared<const Plugin>(std::move(plugin));
    const std::lock_guard lock(mutex_);
    if (const auto it = entry(name); it != entries_.end()) it->second = std::move(owned);
    else entries_.emplace_back(name, std::move(owned));
  }

  // Removes the plugin of `name`; false when there was none. Snapshots already found live on.
  bool remove(std::string_view name) {
    const std::lock_guard lock(mutex_);
    const auto it = entry(name);
    if (it == entries_.end()) return false;
    entries_.erase(it);
    return true;
  }

  // Edits a copy of the plugin of `name` (holders of the old snapshot keep it): `edit(Plugin&)`
  // returns whether it changed anything, and only then does the copy replace the registered
  // plugin. Returns false when `name` is not registered or nothing changed.
  template <class Edit>
  bool update(std::string_view name, Edit&& edit) {
    const std::lock_guard lock(mutex_);
    const auto it = entry(name);
    if (it == entries_.end()) return false;
    auto copy = std::make_shared<Plugin>(*it->second);
    if (!edit(*copy)) return false;
    it->second = std::move(copy);
    return true;
  }

  // The plugin registered under `name`, or nullptr.
  std::shared_ptr<const Plugin> find(std::string_view name) const {
    const std::lock_guard lock(mutex_);
    const auto it = entry(name);
    return it == entries_.end() ? nullptr : it->second;
  }

  bool contains(std::string_view name) const { return find(name) != nullptr; }

  // Registered names, in registration order.
  std::vector<std::string> names() const {
    const std::lock_guard lock(mutex_);
    std::vector<std::string> out;
    for (const auto& [name, plugin] : entries_) out.push_back(name);
    return out;
  }

  // A name this build lacks but a user may ask for: choosing it fails with `why` ("this build
  // has no RHex task: it needs DART"). A plugin registered under that name takes precedence.
  void add_unavailable(const std::string& name, std::string why) {
    const std::lock_guard lock(mutex_);
    unavailable_[name] = std::move(why);
  }

  // Names added as unavailable and not registered since, sorted.
  std::vector<std::string> unavailable_names() const {
    const std::lock_guard lock(mutex_);
    std::vector<std::string> out;
    for (const auto& [name, why] : unavailable_)
      if (entry(name) == entries_.end()) out.push_back(name);
    return out;
  }

  // Why `name` is unavailable, or "" when it was never said to be.
  std::string why_unavailable(std::string_view name) const {
    const std::lock_guard lock(mutex_);
    const auto it = unavailable_.find(name);
    return it == unavailable_.end() ? std::string() : it->second;
  }

 private:
  using Entries = std::vector<std::pair<std::string, std::shared_ptr<const Plugin>>>;
  typename Entries::iterator entry(std::string_view name) {
    return std::find_if(entries_.begin(), entries_.end(), [&](const auto& e) { return e.first == name; });
  }
  typename Entries::const_iterator entry(std::string_view name) const {
    return std::find_if(entries_.begin(), entries_.end(), [&](const auto& e) { return e.first == name; });
  }

  mutable std::mutex mutex_;
  Entries entries_;
  std::map<std::string, std::string, std::less<>> unavailable_;
};

// "\"a\", \"b\"": names as the config reader's messages and docs/config.md list choices.
std::string quoted_names(const std::vector<std::string>& names);

}  // namespace qdmeta
