#include "qdmeta/run/run_state.hpp"

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/run/checkpoint.hpp"
#include "qdmeta/run/summary.hpp"

namespace qdmeta {

RunState::RunState(std::filesystem::path dir)
    : dir_(std::move(dir)),
      has_config_(path_taken(config_path())),
      stop_reason_(stop_reason_of(dir_)),
      has_checkpoint_(std::filesystem::exists(dir_ / kCheckpointFile)) {}

const toml::table& RunState::config() const {
  if (!has_config_) throw InputError(fmt::format("{} holds no run (no config.toml)", dir_.string()));
  if (!config_) config_ = load_toml(config_path());
  return *config_;
}

std::int64_t RunState::budget() const { return config()["budget"]["evaluations"].value_or<std::int64_t>(-1); }

}  // namespace qdmeta
