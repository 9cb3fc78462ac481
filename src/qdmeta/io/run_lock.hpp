#pragma once
// One writer per run directory: `run`, `resume` and each run of an `experiment` hold an
// exclusive lock on the directory for as long as they write to it, so that a second writer is
// refused at once instead of mixing its files with the first one's. Test phases (`adapt`), which
// only add their own files to a finished run, share the lock with each other.
//
// The lock is flock(2) on the directory itself: it is released by the kernel when the process
// ends in any way (kill -9 included), so a crash never leaves a stale lock behind, and no lock
// file is added to the run's files.
#include <filesystem>

namespace qdmeta {

// InputError when a run's files in `dir` would have paths past PATH_MAX (checked before `dir`
// is made, so that a refused run leaves no empty directory behind).
void require_room_for_run_files(const std::filesystem::path& dir);

class RunLock {
 public:
  enum class Mode { kExclusive, kShared };
  enum class Missing { kCreate, kRefuse };
  // Takes the lock without waiting, first creating `dir` when missing if asked to. InputError (a
  // one-line message naming the directory) when another process holds it, `dir` is missing, or
  // (before creating it) its path leaves no room below PATH_MAX for the files a run writes. An
  // exclusive lock removes the temporaries a killed writer left in `dir` (regular_file.hpp).
  RunLock(const std::filesystem::path& dir, Mode mode, Missing missing = Missing::kRefuse);
  ~RunLock();
  RunLock(RunLock&& other) noexcept;
  RunLock& operator=(RunLock&&) = delete;
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace qdmeta
