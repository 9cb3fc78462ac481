#include "qdmeta/eval/mpi/mpi_evaluator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <unordered_map>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/notice.hpp"
#include "qdmeta/eval/mpi/mpi_protocol.hpp"
#include "qdmeta/eval/mpi/mpi_session.hpp"

namespace qdmeta {

std::string describe_tasks(const std::vector<Task>& tasks) {
  std::string out;
  for (const Task& t : tasks)
    out += fmt::format("{}{} ({} genes -> {} base features)", out.empty() ? "" : ", ", t.name(), t.genotype_size(),
                       t.base_feature_size());
  return out;
}

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kInFlight = 2;          // pieces queued per worker: the next is there when one ends
constexpr Index kMaxPieceRows = 256;  // bounds a message and the imbalance at a batch's end

void check(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw EvaluationAborted(fmt::format("MPI error in {}: {}", what, std::string(text, static_cast<std::size_t>(length))));
}

class MpiEvaluator final : public Evaluator {
 public:
  MpiEvaluator(MpiSession& session, std::vector<Task> tasks, const std::string& config, int threads,
               const std::atomic<bool>* stop)
      : session_(session),
        tasks_(std::move(tasks)),
        local_(make_evaluator(threads)),
        stop_(stop),
        timeout_(heartbeat_timeout()),
        heard_(static_cast<std::size_t>(session.size()), Clock::now()) {
    for (std::size_t i = 0; i < tasks_.size(); ++i) index_.emplace(tasks_[i].id(), static_cast<std::int64_t>(i));
    handshake(config, threads);
  }

  void evaluate(const Task& task, GenotypeView genotypes, EvaluationView out) override {
    const EvaluationJob job{&task, genotypes, out};
    evaluate_jobs({&job, 1});
  }
  void evaluate_jobs(std::span<const EvaluationJob> jobs) override;
  int workers() const override { return session_.size() * local_->workers(); }
  void parallel_for(Index n, const std::function<void(Index)>& body) override { local_->parallel_for(n, body); }
  void within_workers(const std::function<void()>& fn) override { local_->within_workers(fn); }
  bool may_abort() const override { return true; }

 private:
  struct Piece {
    const EvaluationJob* job;
    std::int64_t task;
    Index first, rows;
  };
  void handshake(const std::string& config, int threads);
  void send_piece(const Piece& p, std::int64_t id, int worker);
  // Handles every message waiting; returns whether there was one. A worker's failure lands in
  // `failure` (a TaskFailed when the task's own code threw), the first one only.
  bool poll(std::vector<Piece>& pieces, std::vector<std::deque<std::int64_t>>& in_flight, std::size_t& finished,
            std::exception_ptr& failure);
  void abort_if_stopped() const {
    if (stop_ && stop_->load())
      throw EvaluationAborted("the MPI job was stopped (SIGTERM or SIGINT) while a batch was being evaluated");
  }
  // Throws EvaluationAborted (Error while starting: in_flight null) when a worker is found dead:
  // its process is gone (same machine), or it holds pieces and has not been heard from for the
  // heartbeat timeout. Rank 0 finds out by itself: the launcher's signals may come late (after
  // odls_base_sigkill_timeout with OpenMPI) or never.
  void abort_if_dead(const std::vector<std::deque<std::int64_t>>* in_flight);

  MpiSession& session_;
  std::vector<Task> tasks_;
  std::unordered_map<const void*, std::int64_t> index_;
  std::unique_ptr<Evaluator> local_;
  const std::atomic<bool>* stop_;
  const std::chrono::milliseconds timeout_;
  std::vector<Clock::time_point> heard_;  // per rank: the last message, or the first piece after a quiet spell
  Clock::time_point next_check_ = Clock::now();
  mpi::Outbox outbox_;
  std::mutex mutex_;
  std::int64_t request_ = 0;
  Index local_rows_ = 1;  // rank 0's slice between polls, adapted to ~1 ms
  bool warned_ = false;
};

void MpiEvaluator::abort_if_dead(const std::vector<std::deque<std::int64_t>>* in_flight) {
  const auto now = Clock::now();
  if (now < next_check_) return;
  next_check_ = now + std::chrono::milliseconds(10);
  std::string who;
  for (int r = 1; r < session_.size(); ++r) {
    const auto i = static_cast<std::size_t>(r);
    const bool silent = in_flight != nullptr && !(*in_flight)[i].empty() && now - heard_[i] > timeout_;
    // A rank that said goodbye holds its pieces until its signal reaches rank 0 too, unless
    // it has already exited.
    if ((silent && !session_.farewells()[i]) || (!session_.dead(r) && session_.gone(r))) {
      session_.mark_dead(r);
      who += fmt::format("{}{}", who.empty() ? "" : ", ", r);
    }
  }
  if (who.empty()) return;
  if (in_flight == nullptr)
    throw Error(fmt::format("MPI rank{} {} stopped answering (crashed or killed) while starting",
                            who.find(',') != std::string::npos ? "s" : "", who));
  // Mid-run the ranks are named by the CLI (MpiSession::silent_workers), as for a signal.
  throw EvaluationAborted("the batch being evaluated was left unfinished");
}

void MpiEvaluator::handshake(const std::string& config, int threads) {
  mpi::Packer p;
  p.put<std::int64_t>(threads);
  p.put(session_.identity());
  p.put(config.data(), config.size());
  for (int r = 1; r < session_.size(); ++r) outbox_.send(p.bytes(), r, mpi::kConfig, MPI_COMM_WORLD);
  const std::string expected = describe_tasks(tasks_);
  std::vector<bool> ready(static_cast<std::size_t>(session_.size()), false);
  int waiting = session_.size() - 1;
  while (waiting > 0) {
    abort_if_stopped();
    abort_if_dead(nullptr);
    outbox_.progress();
    int flag = 0;
    MPI_Status status;
    check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
    if (!flag) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      continue;
    }
    const std::vector<char> bytes = mpi::receive(status, MPI_COMM_WORLD);
    const int from = status.MPI_SOURCE;
    std::string text(bytes.begin(), bytes.end());
    if (status.MPI_TAG == mpi::kReady) {
      mpi::Unpacker in({bytes.data(), bytes.size()});
      session_.meet(from, in.get<PeerIdentity>());
      text = std::string(in.rest());
    }
    if (status.MPI_TAG == mpi::kBye) {
      session_.farewells()[static_cast<std::size_t>(from)] = true;
      throw EvaluationAborted(fmt::format("rank {} was stopped by a signal while starting", from));
    }
    if (status.MPI_TAG == mpi::kFailed)
      throw Error(fmt::format("MPI rank {}: {}", from, mpi::unpack_failure(text).message));
    if (status.MPI_TAG != mpi::kReady || ready[static_cast<std::size_t>(from)]) continue;
    if (text != expected)
      throw Error(fmt::format("MPI rank {} built other tasks than rank 0 from the same config: [{}] vs [{}]", from, text,
                              expected));
    ready[static_cast<std::size_t>(from)] = true;
    --waiting;
  }
}

void MpiEvaluator::send_piece(const Piece& p, std::int64_t id, int worker) {
  const GenotypeView g = p.job->genotypes.rows(p.first, p.rows);
  mpi::Packer packer;
  packer.put(mpi::WorkHeader{request_, id, p.task, p.rows, g.genotype_size, g.first_row});
  packer.put(g.data, static_cast<std::size_t>(p.rows * g.genotype_size));
  outbox_.send(std::move(packer.bytes()), worker, mpi::kWork, MPI_COMM_WORLD);
}

bool MpiEvaluator::poll(std::vector<Piece>& pieces, std::vector<std::deque<std::int64_t>>& in_flight,
                        std::size_t& finished, std::exception_ptr& failure) {
  bool any = false;
  for (;;) {
    int flag = 0;
    MPI_Status status;
    check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
    if (!flag) return any;
    any = true;
    const std::vector<char> bytes = mpi::receive(status, MPI_COMM_WORLD);
    const int from = status.MPI_SOURCE;
    heard_[static_cast<std::size_t>(from)] = Clock::now();
    auto& mine = in_flight[static_cast<std::size_t>(from)];
    if (status.MPI_TAG == mpi::kBye) {
      session_.farewells()[static_cast<std::size_t>(from)] = true;
      continue;  // a signal is on its way to rank 0 too; the stop flag ends the wait
    }
    if (status.MPI_TAG == mpi::kFailed) {
      const mpi::Failure f = mpi::unpack_failure({bytes.data(), bytes.size()});
      if (!failure) {
        const std::string message = fmt::format("MPI rank {}: {}", from, f.message);
        failure = f.task_failed ? std::make_exception_ptr(TaskFailed(message, f.task, f.row))
                                : std::make_exception_ptr(Error(message));
      }
      if (const auto it = std::find(mine.begin(), mine.end(), f.piece); f.request == request_ && it != mine.end())
        mine.erase(it);
      continue;
    }
    if (status.MPI_TAG != mpi::kResult) continue;
    mpi::Unpacker in({bytes.data(), bytes.size()});
    const auto h = in.get<mpi::ResultHeader>();
    const auto it = std::find(mine.begin(), mine.end(), h.piece);
    if (h.request != request_ || it == mine.end()) continue;  // left over from an aborted request
    mine.erase(it);
    const Piece& p = pieces[static_cast<std::size_t>(h.piece)];
    const EvaluationView out = p.job->out.rows(p.first, p.rows);
    if (h.rows != p.rows || h.base_features != out.base_feature_size)
      throw Error(fmt::format("MPI rank {} returned {} rows x {} base features for a piece of {} x {}", from, h.rows,
                              h.base_features, p.rows, out.base_feature_size));
    in.get(out.fitness, static_cast<std::size_t>(p.rows));
    in.get(out.base_features, static_cast<std::size_t>(p.rows * out.base_feature_size));
    in.get(out.valid, static_cast<std::size_t>(p.rows));
    ++finished;
  }
}

void MpiEvaluator::evaluate_jobs(std::span<const EvaluationJob> jobs) {
  const std::lock_guard lock(mutex_);
  abort_if_stopped();
  ++request_;
  std::vector<Piece> pieces;
  Index total = 0;
  for (const EvaluationJob& j : jobs) {
    const auto it = index_.find(j.task->id());
    if (it == index_.end()) {
      if (!warned_)
        notice(NoticeKind::kWarning,
               fmt::format("task '{}' is not among the run's evaluation tasks: rank 0 evaluates it alone", j.task->name()));
      warned_ = true;
      local_->evaluate(*j.task, j.genotypes, j.out);
      continue;
    }
    total += j.genotypes.count;
  }
  // Guided self-scheduling: each piece takes 1/(2 ranks) of the rows still unassigned, so pieces
  // start large (few messages) and shrink to single rows at the end (ranks finish together).
  const Index ranks = session_.size();
  Index remaining = total;
  for (const EvaluationJob& j : jobs) {
    const auto it = index_.find(j.task->id());
    if (it == index_.end()) continue;
    for (Index first = 0; first < j.genotypes.count;) {
      const Index rows = std::min({std::clamp<Index>(remaining / (2 * ranks), 1, kMaxPieceRows), j.genotypes.count - first});
      pieces.push_back({&j, it->second, first, rows});
      first += rows;
      remaining -= rows;
    }
  }

  std::vector<std::deque<std::int64_t>> in_flight(static_cast<std::size_t>(ranks));
  std::size_t next = 0, finished = 0;
  std::exception_ptr failure;  // the first worker's failure, rethrown once every piece is back
  std::int64_t mine = -1;  // the piece rank 0 is evaluating, row by slice
  Index mine_done = 0;
  const auto outstanding = [&] {
    for (const auto& q : in_flight)
      if (!q.empty()) return true;
    return mine >= 0;
  };
  while (!failure ? finished < pieces.size() : outstanding()) {
    if (!failure)
      for (int w = 1; w < ranks; ++w) {
        auto& q = in_flight[static_cast<std::size_t>(w)];
        // A worker with nothing to do sends no heartbeat: its silence counts from now.
        if (q.empty() && next < pieces.size()) heard_[static_cast<std::size_t>(w)] = Clock::now();
        while (static_cast<int>(q.size()) < kInFlight && next < pieces.size()) {
          send_piece(pieces[next], static_cast<std::int64_t>(next), w);
          q.push_back(static_cast<std::int64_t>(next++));
        }
      }
    outbox_.progress();
    bool busy = poll(pieces, in_flight, finished, failure);
    abort_if_stopped();
    abort_if_dead(&in_flight);
    if (mine < 0 && !failure && next < pieces.size()) {
      mine = static_cast<std::int64_t>(next++);
      mine_done = 0;
    }
    if (mine >= 0) {
      const Piece& p = pieces[static_cast<std::size_t>(mine)];
      const Index n = std::min(local_rows_, p.rows - mine_done);
      const auto start = Clock::now();
      local_->evaluate(*p.job->task, p.job->genotypes.rows(p.first + mine_done, n), p.job->out.rows(p.first + mine_done, n));
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      if (ms < 0.5 && local_rows_ < kMaxPieceRows) local_rows_ *= 2;
      else if (ms > 4.0 && local_rows_ > 1) local_rows_ /= 2;
      mine_done += n;
      if (mine_done == p.rows) {
        mine = -1;
        ++finished;
      }
      busy = true;
    }
    if (!busy) std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace

std::unique_ptr<Evaluator> make_mpi_evaluator(MpiSession& session, std::vector<Task> tasks,
                                              const std::string& config_text, int threads,
                                              const std::atomic<bool>* stop) {
  return std::make_unique<MpiEvaluator>(session, std::move(tasks), config_text, threads, stop);
}

}  // namespace qdmeta
