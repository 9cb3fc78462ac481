#pragma once
// Messages between rank 0 and the workers. Everything goes as MPI_BYTE in one packed buffer
// per message, so a message is one send whatever its size. Internal to eval/mpi.
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta::mpi {

enum Tag : int {
  kConfig = 1,     // 0 -> w: worker threads (int64) + rank 0's PeerIdentity + the resolved config (TOML)
  kReady = 2,      // w -> 0: the worker's PeerIdentity + description of the tasks it built
  kWork = 3,       // 0 -> w: WorkHeader + genotypes (rows x genes Real)
  kResult = 4,     // w -> 0: ResultHeader + fitness + base features + valid
  kFailed = 5,     // w -> 0: a Failure (pack_failure); the worker carries on
  kBye = 6,        // w -> 0: the worker got SIGTERM/SIGINT and exits
  kStop = 7,       // 0 -> w: the end (or, after kBye, exit); answer kStopped, then wait for kFinalize/kAbort
  kAlive = 8,      // w -> 0: heartbeat, every kHeartbeat while the worker holds pieces
  kAbort = 9,      // 0 -> w: a rank died: exit at once (status 3) without MPI_Finalize
  kStopped = 10,   // w -> 0: answer to kStop
  kFinalize = 11,  // 0 -> w: every rank answered kStop: call MPI_Finalize
};

constexpr auto kHeartbeat = std::chrono::milliseconds(200);

struct WorkHeader {
  std::int64_t request = 0;  // serial number of the evaluate call on rank 0
  std::int64_t piece = 0;    // index of the piece within the request
  std::int64_t task = 0;     // index into the evaluation-task list
  std::int64_t rows = 0;
  std::int64_t genes = 0;
  std::int64_t first_row = 0;  // the piece's first row within its batch, for messages
};

struct ResultHeader {
  std::int64_t request = 0;
  std::int64_t piece = 0;
  std::int64_t rows = 0;
  std::int64_t base_features = 0;
};

// Appends raw bytes; reads them back in the same order.
class Packer {
 public:
  template <class T>
  void put(const T* data, std::size_t count) {
    const auto* p = reinterpret_cast<const char*>(data);
    bytes_.insert(bytes_.end(), p, p + count * sizeof(T));
  }
  template <class T>
  void put(const T& x) { put(&x, 1); }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class Unpacker {
 public:
  explicit Unpacker(std::string_view bytes) : bytes_(bytes) {}
  // Throws Error on a short message (a protocol bug, not user input).
  template <class T>
  void get(T* out, std::size_t count) {
    const std::size_t n = count * sizeof(T);
    if (pos_ + n > bytes_.size()) throw Error("MPI message shorter than its header says");
    std::memcpy(out, bytes_.data() + pos_, n);
    pos_ += n;
  }
  template <class T>
  T get() {
    T x;
    get(&x, 1);
    return x;
  }
  std::string_view rest() const { return bytes_.substr(pos_); }

 private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
};

// What a worker reports with kFailed: the piece (or -1 before any), the one-line error, and, when
// a task's own code threw (TaskFailed), the task and its batch row, so that rank 0 ends the run as
// a failed evaluation (exit status 4) rather than as a fault of qdmeta's (2).
struct Failure {
  std::int64_t request = -1, piece = -1;
  std::string message;
  bool task_failed = false;
  std::string task;
  std::int64_t row = -1;  // TaskFailed::row(): -1 when no row threw alone
};

inline std::vector<char> pack_failure(const Failure& f) {
  Packer p;
  p.put(ResultHeader{f.request, f.piece, 0, 0});
  p.put(std::int64_t{f.task_failed ? 1 : 0});
  p.put(f.row);
  p.put(static_cast<std::int64_t>(f.task.size()));
  p.put(f.task.data(), f.task.size());
  p.put(f.message.data(), f.message.size());
  return std::move(p.bytes());
}

inline Failure unpack_failure(std::string_view bytes) {
  Unpacker in(bytes);
  const auto h = in.get<ResultHeader>();
  Failure f{h.request, h.piece, {}, in.get<std::int64_t>() != 0, {}, in.get<std::int64_t>()};
  f.task.resize(static_cast<std::size_t>(in.get<std::int64_t>()));
  in.get(f.task.data(), f.task.size());
  f.message = std::string(in.rest());
  return f;
}

// Receives the message that MPI_Iprobe/MPI_Probe announced in `status`.
inline std::vector<char> receive(const MPI_Status& status, MPI_Comm comm) {
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  std::vector<char> buffer(static_cast<std::size_t>(count));
  MPI_Recv(buffer.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, comm, MPI_STATUS_IGNORE);
  return buffer;
}

}  // namespace qdmeta::mpi

namespace qdmeta::mpi {

// Non-blocking sends whose buffers live until MPI is done with them: a blocking send to a
// rank that died would never return, and a process must be able to notice signals meanwhile.
class Outbox {
 public:
  void send(std::vector<char> bytes, int dest, int tag, MPI_Comm comm) {
    Pending p{MPI_REQUEST_NULL, std::move(bytes)};
    MPI_Isend(p.bytes.data(), static_cast<int>(p.bytes.size()), MPI_BYTE, dest, tag, comm, &p.request);
    pending_.push_back(std::move(p));
  }
  // Forgets the sends that completed.
  void progress() {
    std::erase_if(pending_, [](Pending& p) {
      int done = 0;
      MPI_Test(&p.request, &done, MPI_STATUS_IGNORE);
      return done != 0;
    });
  }
  bool empty() const { return pending_.empty(); }

 private:
  struct Pending {
    MPI_Request request;
    std::vector<char> bytes;
  };
  std::vector<Pending> pending_;
};

}  // namespace qdmeta::mpi
