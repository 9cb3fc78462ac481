// arm-qd: qdmeta's whole command line with one more task, "arm", one more mutation operator,
// "sbx", one more algorithm, "random-search", one more controller of G, "cycle", one more
// feature-map, "polar", and one more archive, "floor".
#include <qdmeta/cli/builtin_plugins.hpp>
#include <qdmeta/cli/run_cli.hpp>

#include "arm_plugin.hpp"
#include "cycle_control.hpp"
#include "floor_archive.hpp"
#include "polar_feature_map.hpp"
#include "random_search.hpp"
#include "sbx.hpp"

int main(int argc, char** argv) {
  qdmeta::register_builtin_plugins();  // Rastrigin, the algorithms (and RHex when linked)
  arm::register_arm_task();            // before run_cli, on every MPI rank
  arm::register_sbx();                 // [mutation] kind = "sbx"
  arm::register_random_search();       // algorithm = "random-search"
  arm::register_cycle_control();       // [control] kind = "cycle"
  arm::register_polar_feature_map();   // [feature_map] kind = "polar"
  arm::register_floor_archive();       // [archive] kind = "floor"
  return qdmeta::run_cli(argc, argv);
}
