#include "qdmeta/run/run_state.hpp"

#include <fmt/format.h>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/run/checkpoint.hpp"

namespace qdmeta {

RunState::RunState(std::filesystem::path dir)
    : dir_(std::move(dir)),
      has_config_(path_taken(config_path())),
      summary_(read_summary(dir_)),
      has_checkpoint_(std::filesystem::exists(dir_ / kCheckpointFile)) {}

const toml::table& RunState::config() const {
  if (!has_config_) throw InputError(fmt::format("{} holds no run (no config.toml)", dir_.string()));
  if (!config_) config_ = load_toml(config_path());
  return *config_;
}

std::int64_t RunState::budget() const { return configured_budget(config()).value_or(-1); }

}  // namespace qdmeta
