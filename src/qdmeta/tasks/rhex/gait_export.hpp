#pragma once
// Gait export: the poses of a recorded episode (EpisodeSettings::record_poses) to a CSV file and
// to a self-contained HTML page that replays the walk in a side view and a top view. DART-free.
#include <filesystem>
#include <string>

#include "qdmeta/tasks/rhex/rhex_episode.hpp"

namespace qdmeta::rhex {

// Columns: time,x,y,z,roll,pitch,yaw,leg_0..leg_5 (m, rad), one row per recorded step.
void write_gait_csv(const EpisodeResult& episode, const std::filesystem::path& path);

// An HTML page with an inline SVG animated by a few lines of JavaScript, playing the recorded
// steps (every `stride`-th) in real time, in a loop. `title` heads the page.
void write_gait_html(const EpisodeResult& episode, const std::filesystem::path& path, const std::string& title,
                     int stride = 4);

}  // namespace qdmeta::rhex
