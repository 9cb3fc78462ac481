// arm-qd: qdmeta's whole command line with one more task, "arm", and one more mutation operator,
// "sbx".
#include <qdmeta/cli/builtin_plugins.hpp>
#include <qdmeta/cli/run_cli.hpp>

#include "arm_plugin.hpp"
#include "sbx.hpp"

int main(int argc, char** argv) {
  qdmeta::register_builtin_plugins();  // Rastrigin, the algorithms (and RHex when linked)
  arm::register_arm_task();            // before run_cli, on every MPI rank
  arm::register_sbx();                 // [mutation] kind = "sbx"
  return qdmeta::run_cli(argc, argv);
}
