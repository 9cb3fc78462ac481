#pragma once
// The one exception type of the library. Library code throws it (never aborts, and never exits
// but in one place: an MPI worker rank, whose program handed its process to the worker loop,
// leaves by std::quick_exit when rank 0 is gone or a signal comes while its compute thread runs,
// since neither MPI_Finalize nor joining that thread would return); the CLI turns it into a
// one-line message and exit status 2.
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>

namespace qdmeta {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// Raised for invalid user input: bad config keys or values, missing files, size mismatches.
class InputError : public Error {
 public:
  explicit InputError(const std::string& message) : Error(message) {}
};

// Raised by an evaluator that cannot finish a batch: a distributed worker died, or the job was
// stopped (SIGTERM) while results were outstanding. The batch's outputs are incomplete, so the
// run driver discards the step and checkpoints the state before it.
class EvaluationAborted : public Error {
 public:
  explicit EvaluationAborted(const std::string& message) : Error(message) {}
};

// A task's own code threw (anything but a qdmeta::Error) while evaluating a batch. Names the
// task and the batch row that threw, and nests the original (std::rethrow_if_nested). The step
// it happened in is undone, so a run can continue from its last checkpoint once the task is fixed.
class TaskFailed : public Error, public std::nested_exception {
 public:
  TaskFailed(const std::string& message, std::string task, long long row)
      : Error(message), task_(std::move(task)), row_(row) {}
  const std::string& task() const { return task_; }
  // The batch row that threw, or -1 when none threw alone (the rows of `what()` then threw together).
  long long row() const { return row_; }

 private:
  std::string task_;
  long long row_;
};

// Raised from inside a step to stop it at the user's request (Ctrl-C while a task's own code
// ran): step() undoes the step, and the run driver ends the run there as interrupted, its files
// written, before passing the exception on.
class StepInterrupted : public Error {
 public:
  explicit StepInterrupted(const std::string& message) : Error(message) {}
};

}  // namespace qdmeta
