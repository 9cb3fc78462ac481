#pragma once
// The plugins of the components this program links: the core's (Rastrigin, the four
// algorithms) register themselves on first use; the RHex task when the program links qdmeta::rhex,
// whose QDMETA_WITH_RHEX compile definition reaches this header. Inline, so that the choice is the
// program's, not the one the CLI library was compiled with.
#include "qdmeta/assembly/core_plugins.hpp"
#ifdef QDMETA_WITH_RHEX
#include "qdmeta/tasks/rhex/rhex_config.hpp"
#endif

namespace qdmeta {

inline void register_builtin_plugins() {
  ensure_core_plugins();
#ifdef QDMETA_WITH_RHEX
  register_rhex_task();  // [task] name = "rhex"
#endif
}

}  // namespace qdmeta
