#include "qdmeta/control/controller.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

StaticControl::StaticControl(int generations) : generations_(generations) {
  require(kGenerations, generations);
}

}  // namespace qdmeta
