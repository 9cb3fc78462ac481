#include "qdmeta/cli/distribution_factory.hpp"

#include "qdmeta/cli/distribution.hpp"

namespace qdmeta {

std::unique_ptr<Distribution> make_local_distribution(int& /*argc*/, char**& /*argv*/) {
  return std::make_unique<Distribution>();
}

}  // namespace qdmeta
