#pragma once
// What every build of the library offers without asking: the Rastrigin task with its
// meta-objectives and test families, the four algorithms, and a hint for the RHex task of a build
// without DART. Every registry lookup registers them first (once, thread-safely), so a program
// that only calls build_run() needs no set-up; a plugin registered under the same name before
// or after replaces the built-in one.
namespace qdmeta {

// Registers the built-in plugins now if no lookup has yet; idempotent.
void ensure_core_plugins();

}  // namespace qdmeta
