#pragma once
// Files of a run directory as a damaged or hostile directory may hold them. Reading: only a
// regular file is read (a FIFO in its place would block forever, /dev/zero would fill memory),
// and only up to a bound. Writing: a file is created anew, never through a symbolic link planted
// where it goes (the link is replaced, not followed), and temporary files have names of their
// own, so two processes that write the same file at once do not share one.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace qdmeta {

inline constexpr std::uint64_t kMiB = std::uint64_t{1} << 20;
inline constexpr std::uint64_t kGiB = std::uint64_t{1} << 30;

// The bounds of what qdmeta reads: far above anything it writes, far below what would hurt.
inline constexpr std::uint64_t kMaxTextFileBytes = 64 * kMiB;    // configs, summaries, experiment files
inline constexpr std::uint64_t kMaxTableFileBytes = 4 * kGiB;    // archive.csv, metrics.csv, meta.csv
inline constexpr std::uint64_t kMaxBinaryFileBytes = 64 * kGiB;  // checkpoints, centroid caches

// The size of the regular file at `path` (a link to one counts). InputError naming the file
// when it is missing, is not a regular file (saying what it is instead) or holds more than
// `max_bytes`.
std::uint64_t regular_file_size(const std::filesystem::path& path, std::uint64_t max_bytes);

// The whole content of the regular file at `path`, under the same rules.
std::string read_regular_file(const std::filesystem::path& path, std::uint64_t max_bytes);

// Whether anything, a dangling link included, is at `path` (std::filesystem::exists follows links).
bool path_taken(const std::filesystem::path& path);

// A new file at `path`, open for writing: whatever stood there (a file, a link) is removed first
// and the file is created exclusively, so a planted link is never followed. Returns the file
// descriptor; Error when it cannot be made.
int create_file_replacing(const std::filesystem::path& path);

// InputError when `path` is a symbolic link: a file qdmeta continues (appends to) must be its own.
void refuse_symbolic_link(const std::filesystem::path& path);

// An existing regular file at `path`, open for appending, refused (InputError) when it is a link
// or not a regular file.
int open_file_for_append(const std::filesystem::path& path);

// A new temporary file beside `path` with a name no other writer uses ("<name>.tmp-<pid>-<n>"),
// created exclusively. Sets `tmp_path` and returns the file descriptor.
int create_temporary_beside(const std::filesystem::path& path, std::filesystem::path& tmp_path);

// Whether `filename` has the form create_temporary_beside gives ("<name>.tmp-<pid>-<n>").
bool is_temporary_name(std::string_view filename);

// Removes the temporaries of dead writers from `dir` (not its subfolders). Only for a caller that
// holds the directory's exclusive run lock (io/run_lock.hpp): then no live writer has one there,
// and whatever temporary stands there was left by a process killed (kill -9, SIGXFSZ) between
// creating and renaming it. Returns how many were removed.
int remove_dead_temporaries(const std::filesystem::path& dir);

// The room a run directory's path must leave below PATH_MAX for the longest name written in it
// (a test phase's temporary, "adapt-<test>.csv.tmp-<pid>-<n>").
inline constexpr std::size_t kRunFileNameRoom = 128;

// Writes all of `bytes` to `fd`; Error naming `path` when the write fails (EFBIG names the file
// size limit: the process ignores SIGXFSZ so that the write fails instead of killing it).
void write_all(int fd, std::string_view bytes, const std::filesystem::path& path);

}  // namespace qdmeta
