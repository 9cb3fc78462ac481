#pragma once
// What every build of the library offers without asking: the Rastrigin task with its
// meta-objectives and test families, the four algorithms, the controllers "static" and "sarsa"
// (plugin/part_registries.hpp), and a hint for the RHex task of a build
// without DART. They register as a user's plugins do, through register_task_plugin() and
// register_algorithm(); the registries themselves know nothing of them.
namespace qdmeta {

// Registers the built-in plugins once per process (later calls do nothing), each only where no
// plugin of its name is registered yet: a user's plugin of a built-in name wins, whether it was
// registered before this call or after. build_run() and the other config readers of
// assembly/build.hpp call it, so a program that only builds runs needs no set-up; a main calls
// it through register_builtin_plugins() (cli/builtin_plugins.hpp).
void ensure_core_plugins();

}  // namespace qdmeta
