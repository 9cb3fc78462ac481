#pragma once
#include <string_view>

namespace qdmeta {
inline constexpr std::string_view kVersion = QDMETA_VERSION;  // set by CMake from project(VERSION)
}
