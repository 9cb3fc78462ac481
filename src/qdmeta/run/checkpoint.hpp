#pragma once
// A run's checkpoint: everything needed to continue it bit-identically (the algorithm's state
// and the run driver's place in its logs), in one versioned binary file written atomically.
// Reading checks the magic, the format version, a checksum of the whole file and the config
// fingerprint, so a corrupt or mismatched file stops with a clear InputError, never a silent
// restart.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include <toml++/toml.h>

#include "qdmeta/algorithms/algorithm.hpp"

namespace qdmeta {

// Format 2: the checksum covers the whole file (format 1 left the header outside it). Format 3:
// QD-Meta's last meta-generation record carries its meta-population statistics.
inline constexpr std::uint32_t kCheckpointFormat = 4;  // 4: the logs' hashes
inline constexpr const char* kCheckpointFile = "checkpoint.bin";

// Which checkpoints resume. A checkpoint records the format of its bytes and the program version
// that wrote it; the format says whether this program can read it, the version whether what it
// read continues to the same bits (another version may draw, round or order differently). So a
// checkpoint resumes when its format is kCheckpointFormat and its version is this program's or
// one listed here: versions whose checkpoints this one is known to continue bit-identically (the
// goldens, tests/cli/golden_test.cpp, and a checkpoint of that version resumed by this one give
// the bits of an uninterrupted run). A version bump that changes no result adds the old version
// here; one that changes results leaves it out, and its checkpoints are refused, naming both
// versions. The version is at most kMaxVersionBytes of [0-9A-Za-z.+-]; anything else is damage.
// 0.2.0 and 0.3.0 broke APIs, not results.
inline constexpr std::array<std::string_view, 2> kCheckpointResumesFrom{"0.1.0", "0.2.0"};
inline constexpr std::size_t kMaxVersionBytes = 64;

// The run driver's own state between two generations.
struct RunCursor {
  std::int64_t next_log = 0;                // evaluation count of the next metrics row
  std::int64_t last_logged_generation = -1;
  std::uint64_t metrics_bytes = 0;          // metrics.csv's length at the checkpoint
  std::uint64_t meta_bytes = 0;             // meta.csv's length (0: not started)
  std::uint64_t metrics_hash = 0;           // FNV-1a of metrics.csv's first metrics_bytes bytes
  std::uint64_t meta_hash = 0;              // and of meta.csv's first meta_bytes bytes
  double wall_seconds = 0.0;                // run time before the checkpoint
  std::int64_t checkpoints = 0;             // checkpoints written so far, this one included
  bool operator==(const RunCursor&) const = default;
};

// A run's state between two steps, in memory: a distributed run takes one before every step,
// so that when a step cannot finish (a worker died) the state before it can still be written.
struct RunSnapshot {
  RunCursor cursor;
  std::string algorithm_name;
  std::string algorithm_state;  // Algorithm::save's bytes
};
RunSnapshot take_snapshot(const RunCursor& cursor, const Algorithm& algorithm);

// Writes <dir>/checkpoint.bin atomically. The algorithm must be checkpointable.
void write_checkpoint(const std::filesystem::path& dir, std::uint64_t fingerprint, const RunCursor& cursor,
                      const Algorithm& algorithm);
void write_checkpoint(const std::filesystem::path& dir, std::uint64_t fingerprint, const RunSnapshot& snapshot);

// Restores `algorithm` (freshly built from the same config) and returns the cursor. Refuses
// (InputError) a checkpoint of another format or of a version it does not resume (above), and
// one whose archive holds a value no run writes (an objective or feature that is not finite, a
// gene outside [0, 1], a stored base feature outside [-1, 1], as `qdmeta adapt` refuses in archive.csv).
RunCursor read_checkpoint(const std::filesystem::path& dir, std::uint64_t fingerprint, Algorithm& algorithm);

}  // namespace qdmeta
