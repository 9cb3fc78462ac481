// The qdmeta executable: the built-in plugins and the command line of the library (run_cli.hpp).
#include "qdmeta/cli/builtin_plugins.hpp"
#include "qdmeta/cli/run_cli.hpp"

int main(int argc, char** argv) {
  qdmeta::register_builtin_plugins();
  return qdmeta::run_cli(argc, argv);
}
