#include "qdmeta/eval/mpi/mpi_worker.hpp"

#include <csignal>
#include <cstdlib>
#include <deque>
#include <future>
#include <string>
#include <thread>

#include "qdmeta/core/exit_status.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/eval/mpi/mpi_evaluator.hpp"
#include "qdmeta/eval/mpi/mpi_protocol.hpp"
#include "qdmeta/eval/mpi/mpi_session.hpp"

namespace qdmeta {
namespace {

volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_worker_signal(int s) { g_signal = s; }

struct Work {
  mpi::WorkHeader header;
  std::vector<Real> genes;
};

constexpr long kKillAtStop = -2;

// The test hook's piece count, kKillAtStop, or -1 when it is not aimed at this rank.
long kill_after(int rank) {
  const char* who = std::getenv("QDMETA_TEST_KILL_RANK");
  const char* after = std::getenv("QDMETA_TEST_KILL_AFTER");
  if (who == nullptr || after == nullptr || std::atoi(who) != rank) return -1;
  if (std::string(after) == "stop") return kKillAtStop;
  return std::atol(after);
}

// The test hook's signal: SIGKILL, or SIGSTOP (a hung rank) with QDMETA_TEST_KILL_SIGNAL=STOP.
int kill_signal() {
  const char* name = std::getenv("QDMETA_TEST_KILL_SIGNAL");
  return name != nullptr && std::string(name) == "STOP" ? SIGSTOP : SIGKILL;
}

using Clock = std::chrono::steady_clock;

// Rank 0 vanished (on this machine): nobody will ever release this rank, and the launcher may
// wait long before it signals, so leave now (no MPI_Finalize: it would wait for rank 0).
struct Rank0Watch {
  const MpiSession& session;
  Clock::time_point next = Clock::now();
  void check() {
    if (Clock::now() < next) return;
    next = Clock::now() + std::chrono::milliseconds(50);
    if (session.gone(0)) std::quick_exit(kExitRankFailed);
  }
};

std::vector<char> failed(const mpi::WorkHeader& h, const std::string& message) {
  return mpi::pack_failure({h.request, h.piece, message, false, {}, -1});
}

// A task's own code threw: rank 0 rethrows it as TaskFailed, with the task and batch row.
std::vector<char> task_failed(const mpi::WorkHeader& h, const TaskFailed& e) {
  return mpi::pack_failure({h.request, h.piece, e.what(), true, e.task(), e.row()});
}

std::vector<char> evaluate(const Work& w, const Task& task, Evaluator& evaluator) {
  EvaluationBatch out;
  out.resize(w.header.rows, task.base_feature_size());
  evaluator.evaluate(task, {w.genes.data(), w.header.rows, w.header.genes, w.header.first_row}, out.view());
  mpi::Packer p;
  p.put(mpi::ResultHeader{w.header.request, w.header.piece, w.header.rows, task.base_feature_size()});
  p.put(out.fitness.data(), static_cast<std::size_t>(out.size()));
  p.put(out.base_features.data(), static_cast<std::size_t>(out.base_features.size()));
  p.put(out.valid.data(), out.valid.size());
  return std::move(p.bytes());
}

}  // namespace

int run_mpi_worker(MpiSession& session, const TaskListBuilder& build) {
  std::signal(SIGTERM, on_worker_signal);
  std::signal(SIGINT, on_worker_signal);
  const long kill_at = kill_after(session.rank());
  const int kill_with = kill_signal();
  long received = 0;
  Rank0Watch watch{session};
  auto last_beat = Clock::now();
  std::vector<Task> tasks;
  std::unique_ptr<Evaluator> evaluator = make_evaluator(1);
  std::deque<Work> queue;
  mpi::WorkHeader running_header;
  std::future<std::vector<char>> running;  // the packed result of the piece being evaluated
  mpi::Outbox outbox;
  const auto finish_running = [&] {
    try {
      outbox.send(running.get(), 0, mpi::kResult, MPI_COMM_WORLD);
    } catch (const TaskFailed& e) {
      outbox.send(task_failed(running_header, e), 0, mpi::kFailed, MPI_COMM_WORLD);
    } catch (const std::exception& e) {
      outbox.send(failed(running_header, e.what()), 0, mpi::kFailed, MPI_COMM_WORLD);
    }
  };

  for (;;) {
    if (g_signal != 0) {
      // Tell rank 0 this rank is alive and stopping, so that it can name the one that died; then
      // stay until rank 0 has had its say (mpirun drops rank 0's output once all other ranks
      // have exited), at most until mpirun's SIGKILL or 10 s.
      outbox.send({}, 0, mpi::kBye, MPI_COMM_WORLD);
      const auto until = Clock::now() + std::chrono::seconds(10);
      for (bool released = false; !released && Clock::now() < until && !session.gone(0);) {
        outbox.progress();
        int waiting = 0;
        MPI_Status s;
        MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &waiting, &s);
        if (waiting) {
          mpi::receive(s, MPI_COMM_WORLD);
          released = s.MPI_TAG == mpi::kStop || s.MPI_TAG == mpi::kAbort;
        } else {
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
      }
      session.abandon();
      if (running.valid()) std::quick_exit(128 + g_signal);  // the compute thread cannot be joined in time
      return 128 + g_signal;
    }
    outbox.progress();
    watch.check();
    // The heartbeat, while rank 0 waits for this rank's pieces (idle workers stay quiet, so
    // nothing piles up on rank 0 between batches).
    if ((running.valid() || !queue.empty()) && Clock::now() - last_beat >= mpi::kHeartbeat) {
      outbox.send({}, 0, mpi::kAlive, MPI_COMM_WORLD);
      last_beat = Clock::now();
    }
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
    if (flag) {
      const std::vector<char> bytes = mpi::receive(status, MPI_COMM_WORLD);
      mpi::Unpacker in({bytes.data(), bytes.size()});
      if (status.MPI_TAG == mpi::kAbort) std::quick_exit(kExitRankFailed);
      if (status.MPI_TAG == mpi::kStop) {
        if (kill_at == kKillAtStop) std::raise(kill_with);
        if (running.valid()) running.wait();
        outbox.send({}, 0, mpi::kStopped, MPI_COMM_WORLD);
        // MPI_Finalize waits for every rank: only when rank 0 says that all are there.
        for (;;) {
          outbox.progress();
          watch.check();
          if (g_signal != 0) {
            session.abandon();
            return 128 + g_signal;
          }
          MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
          if (!flag) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            continue;
          }
          mpi::receive(status, MPI_COMM_WORLD);
          if (status.MPI_TAG == mpi::kAbort) std::quick_exit(kExitRankFailed);
          if (status.MPI_TAG == mpi::kFinalize) {
            while (!outbox.empty()) {
              outbox.progress();
              watch.check();
            }
            return 0;
          }
        }
      }
      if (status.MPI_TAG == mpi::kConfig) {
        const auto threads = in.get<std::int64_t>();
        session.meet(0, in.get<PeerIdentity>());
        try {
          tasks = build(std::string(in.rest()));
          evaluator = make_evaluator(static_cast<int>(threads));
          mpi::Packer ready;
          ready.put(session.identity());
          const std::string d = describe_tasks(tasks);
          ready.put(d.data(), d.size());
          outbox.send(std::move(ready.bytes()), 0, mpi::kReady, MPI_COMM_WORLD);
        } catch (const std::exception& e) {
          outbox.send(failed({-1, -1, 0, 0, 0}, e.what()), 0, mpi::kFailed, MPI_COMM_WORLD);
        }
      } else if (status.MPI_TAG == mpi::kWork) {
        if (kill_at >= 0 && ++received > kill_at) std::raise(kill_with);
        Work w;
        w.header = in.get<mpi::WorkHeader>();
        w.genes.resize(static_cast<std::size_t>(w.header.rows * w.header.genes));
        in.get(w.genes.data(), w.genes.size());
        queue.push_back(std::move(w));
      }
      continue;
    }
    if (running.valid() && running.wait_for(std::chrono::seconds(0)) == std::future_status::ready) finish_running();
    if (!running.valid() && !queue.empty()) {
      auto w = std::make_shared<Work>(std::move(queue.front()));
      queue.pop_front();
      running_header = w->header;
      if (w->header.task < 0 || w->header.task >= static_cast<std::int64_t>(tasks.size())) {
        outbox.send(failed(w->header, "piece for an unknown task"), 0, mpi::kFailed, MPI_COMM_WORLD);
        continue;
      }
      const Task* task = &tasks[static_cast<std::size_t>(w->header.task)];
      Evaluator* e = evaluator.get();
      running = std::async(std::launch::async, [w, task, e] { return evaluate(*w, *task, *e); });
      continue;
    }
    if (running.valid()) running.wait_for(std::chrono::microseconds(200));
    else std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
}

}  // namespace qdmeta
