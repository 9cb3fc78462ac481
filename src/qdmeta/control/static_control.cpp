#include "qdmeta/control/controller.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

StaticControl::StaticControl(int generations) : generations_(generations) {
  require_range("control.generations", generations, 1, 1'000'000);
}

}  // namespace qdmeta
