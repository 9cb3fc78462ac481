#include "qdmeta/experiment/core_plugins.hpp"

#include <mutex>

#include "qdmeta/experiment/builtin_algorithms.hpp"
#include "qdmeta/experiment/task_registry.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_config.hpp"

namespace qdmeta {
namespace {

// Set while the built-ins register themselves: their own register_* calls must not wait for
// the std::call_once they run inside.
thread_local bool t_registering_core = false;

// Before a user's registrations, so that theirs replace the built-ins, never the reverse.
void register_core_plugins() {
  register_unavailable_task("rhex", "this build has no RHex task: it needs DART");
  register_rastrigin_task();
  register_builtin_algorithms();
}

}  // namespace

void ensure_core_plugins() {
  static std::once_flag once;
  if (t_registering_core) return;
  std::call_once(once, [] {
    t_registering_core = true;
    register_core_plugins();
    t_registering_core = false;
  });
}

}  // namespace qdmeta
