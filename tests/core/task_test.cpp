// Tests of src/qdmeta/core/task.{hpp,cpp}: the Task value wrapper around user task types —
// optional members and their defaults, size checks, output checks (NaN fitness, base features
// outside [0, 1]) on valid rows only, clone() independence, and a task's own exception named by
// the batch row that threw.
#include "qdmeta/core/task.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/evaluation_batch.hpp"

namespace qdmeta {
namespace {

// Only the required members: fitness = sum of genes, base features = the first two genes.
struct MinimalTask {
  Index genotype_size() const { return 3; }
  Index base_feature_size() const { return 2; }
  void evaluate(GenotypeView g, EvaluationView e) const {
    for (Index i = 0; i < g.count; ++i) {
      const Real* x = g.row(i);
      e.fitness[i] = x[0] + x[1] + x[2];
      e.base_row(i)[0] = x[0];
      e.base_row(i)[1] = x[1];
      e.valid[i] = 1;
    }
  }
};
static_assert(UserTask<MinimalTask>);

// Every optional member, with non-default values.
struct FullTask : MinimalTask {
  std::string name() const { return "toy"; }
  bool shareable() const { return true; }
  double qd_offset() const { return -5.0; }
};

// Writes a chosen bad value into one row; that row's valid flag is chosen too.
struct BadTask {
  enum class Fault { kNone, kNanFitness, kInfFitness, kBaseAbove, kBaseBelow, kBaseNan };
  Fault fault = Fault::kNone;
  Index bad_row = 0;
  std::uint8_t bad_row_valid = 1;
  std::string name() const { return "bad-task"; }
  Index genotype_size() const { return 2; }
  Index base_feature_size() const { return 3; }
  void evaluate(GenotypeView g, EvaluationView e) const {
    for (Index i = 0; i < g.count; ++i) {
      e.fitness[i] = 1.0f;
      for (Index j = 0; j < 3; ++j) e.base_row(i)[j] = (j == 0) ? 0.0f : (j == 1 ? 1.0f : 0.5f);  // ends are valid
      e.valid[i] = 1;
    }
    if (bad_row >= g.count) return;
    e.valid[bad_row] = bad_row_valid;
    switch (fault) {
      case Fault::kNone: break;
      case Fault::kNanFitness: e.fitness[bad_row] = std::numeric_limits<Real>::quiet_NaN(); break;
      case Fault::kInfFitness: e.fitness[bad_row] = -std::numeric_limits<Real>::infinity(); break;
      case Fault::kBaseAbove: e.base_row(bad_row)[2] = 1.5f; break;
      case Fault::kBaseBelow: e.base_row(bad_row)[1] = -0.25f; break;
      case Fault::kBaseNan: e.base_row(bad_row)[2] = std::numeric_limits<Real>::quiet_NaN(); break;
    }
  }
};

// Counts its own calls, so a clone's state can be told apart from the original's.
struct CountingTask {
  mutable int calls = 0;
  std::string label = "counter";
  std::string name() const { return label; }
  Index genotype_size() const { return 1; }
  Index base_feature_size() const { return 0; }
  void evaluate(GenotypeView g, EvaluationView e) const {
    ++calls;
    for (Index i = 0; i < g.count; ++i) {
      e.fitness[i] = static_cast<Real>(calls);
      e.valid[i] = 1;
    }
  }
};

struct SizedTask {
  Index genes = 1;
  Index bases = 0;
  std::string name() const { return "sized"; }
  Index genotype_size() const { return genes; }
  Index base_feature_size() const { return bases; }
  void evaluate(GenotypeView, EvaluationView) const {}
};

std::string error_of(const Task& task, GenotypeView g, EvaluationView e) {
  try {
    task.evaluate(g, e);
  } catch (const Error& err) {
    return err.what();
  }
  return "(no exception)";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(Task, DefaultsApplyWhenOptionalMembersAreAbsent) {
  const Task task{MinimalTask{}};
  EXPECT_EQ(task.name(), "task");
  EXPECT_FALSE(task.shareable());
  EXPECT_EQ(task.qd_offset(), 0.0);
  EXPECT_EQ(task.genotype_size(), 3);
  EXPECT_EQ(task.base_feature_size(), 2);
}

TEST(Task, OptionalMembersArePickedUp) {
  const Task task{FullTask{}};
  EXPECT_EQ(task.name(), "toy");
  EXPECT_TRUE(task.shareable());
  EXPECT_EQ(task.qd_offset(), -5.0);
}

TEST(Task, EvaluatesThroughTheUserType) {
  const Task task{MinimalTask{}};
  RowMatrix g(2, 3);
  g << 0.1f, 0.2f, 0.3f, 0.9f, 0.0f, 1.0f;
  EvaluationBatch out;
  out.resize(2, 2);
  task.evaluate({g.data(), 2, 3}, out.view());
  EXPECT_FLOAT_EQ(out.fitness[0], 0.6f);
  EXPECT_FLOAT_EQ(out.fitness[1], 1.9f);
  EXPECT_EQ(out.base_features(1, 0), 0.9f);
  EXPECT_EQ(out.base_features(1, 1), 0.0f);
  EXPECT_EQ(out.valid, (std::vector<std::uint8_t>{1, 1}));
}

TEST(Task, SizeMismatchesThrowNamingTheTask) {
  const Task task{FullTask{}};
  RowMatrix g4(2, 4);
  g4.setConstant(0.5f);
  RowMatrix g3(2, 3);
  g3.setConstant(0.5f);
  EvaluationBatch out;
  out.resize(2, 2);

  const std::string genes = error_of(task, {g4.data(), 2, 4}, out.view());
  EXPECT_EQ(genes, "task 'toy': genotypes have 4 genes, the task expects 3");

  EvaluationBatch wide;
  wide.resize(2, 5);
  const std::string bases = error_of(task, {g3.data(), 2, 3}, wide.view());
  EXPECT_TRUE(contains(bases, "task 'toy'")) << bases;
  EXPECT_TRUE(contains(bases, "5")) << bases;
  EXPECT_TRUE(contains(bases, "2")) << bases;

  EvaluationBatch short_out;
  short_out.resize(1, 2);
  const std::string count = error_of(task, {g3.data(), 2, 3}, short_out.view());
  EXPECT_TRUE(contains(count, "task 'toy'")) << count;
  EXPECT_TRUE(contains(count, "2 genotypes")) << count;
  EXPECT_TRUE(contains(count, "room for 1")) << count;
}

TEST(Task, InvalidSizesThrowAtConstruction) {
  try {
    Task task{SizedTask{0, 0}};
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "task 'sized'")) << e.what();
    EXPECT_TRUE(contains(e.what(), "got 0")) << e.what();
  }
  try {
    Task task{SizedTask{2, -1}};
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "task 'sized'")) << e.what();
    EXPECT_TRUE(contains(e.what(), "got -1")) << e.what();
  }
  EXPECT_NO_THROW((Task{SizedTask{1, 0}}));
}

struct FaultCase {
  BadTask::Fault fault;
  std::string expected;  // the whole message
};

TEST(Task, BadOutputOnAValidRowThrowsWithTheRowIndex) {
  const FaultCase cases[] = {
      {BadTask::Fault::kNanFitness, "task 'bad-task': fitness of solution 3 is nan"},
      {BadTask::Fault::kInfFitness, "task 'bad-task': fitness of solution 3 is -inf"},
      {BadTask::Fault::kBaseAbove, "task 'bad-task': base feature 2 of solution 3 is 1.5, outside [0, 1]" + std::string(kBaseFeatureRangeHint)},
      {BadTask::Fault::kBaseBelow, "task 'bad-task': base feature 1 of solution 3 is -0.25, outside [0, 1]" + std::string(kBaseFeatureRangeHint)},
      {BadTask::Fault::kBaseNan, "task 'bad-task': base feature 2 of solution 3 is nan, outside [0, 1]" + std::string(kBaseFeatureRangeHint)},
  };
  RowMatrix g(5, 2);
  g.setConstant(0.5f);
  for (const auto& c : cases) {
    const Task task{BadTask{c.fault, 3, 1}};
    EvaluationBatch out;
    out.resize(5, 3);
    EXPECT_EQ(error_of(task, {g.data(), 5, 2}, out.view()), c.expected);
  }
}

TEST(Task, InvalidRowsAreNotChecked) {
  RowMatrix g(5, 2);
  g.setConstant(0.5f);
  for (auto fault : {BadTask::Fault::kNanFitness, BadTask::Fault::kInfFitness, BadTask::Fault::kBaseAbove,
                     BadTask::Fault::kBaseBelow, BadTask::Fault::kBaseNan}) {
    const Task task{BadTask{fault, 3, 0}};
    EvaluationBatch out;
    out.resize(5, 3);
    EXPECT_NO_THROW(task.evaluate({g.data(), 5, 2}, out.view()));
    EXPECT_EQ(out.valid[3], 0);
  }
  // Features exactly 0 and 1 are valid.
  const Task ok{BadTask{BadTask::Fault::kNone, 0, 1}};
  EvaluationBatch out;
  out.resize(5, 3);
  EXPECT_NO_THROW(ok.evaluate({g.data(), 5, 2}, out.view()));
}

TEST(Task, FirstBadRowIsNamed) {
  // Rows 1 and 3 are bad; row 1 is reported.
  struct TwoBad {
    std::string name() const { return "two"; }
    Index genotype_size() const { return 1; }
    Index base_feature_size() const { return 1; }
    void evaluate(GenotypeView g, EvaluationView e) const {
      for (Index i = 0; i < g.count; ++i) {
        e.fitness[i] = 0;
        e.base_row(i)[0] = (i == 1 || i == 3) ? 2.0f : 0.5f;
        e.valid[i] = 1;
      }
    }
  };
  const Task task{TwoBad{}};
  RowMatrix g(4, 1);
  g.setZero();
  EvaluationBatch out;
  out.resize(4, 1);
  EXPECT_EQ(error_of(task, {g.data(), 4, 1}, out.view()), "task 'two': base feature 0 of solution 1 is 2, outside [0, 1]" + std::string(kBaseFeatureRangeHint));
}

TEST(Task, CopiesShareCloneDoesNot) {
  const Task task{CountingTask{}};
  const Task copy = task;  // NOLINT(performance-unnecessary-copy-initialization): testing copy semantics
  EXPECT_EQ(copy.id(), task.id());

  RowMatrix g(1, 1);
  g.setZero();
  EvaluationBatch out;
  out.resize(1, 0);
  task.evaluate({g.data(), 1, 1}, out.view());
  EXPECT_EQ(out.fitness[0], 1.0f);

  const Task clone = task.clone();
  EXPECT_NE(clone.id(), task.id());
  EXPECT_EQ(clone.name(), "counter");
  EXPECT_EQ(clone.genotype_size(), 1);
  EXPECT_EQ(clone.base_feature_size(), 0);

  // The clone starts from the original's state (1 call) and then diverges.
  clone.evaluate({g.data(), 1, 1}, out.view());
  EXPECT_EQ(out.fitness[0], 2.0f);
  clone.evaluate({g.data(), 1, 1}, out.view());
  EXPECT_EQ(out.fitness[0], 3.0f);
  task.evaluate({g.data(), 1, 1}, out.view());
  EXPECT_EQ(out.fitness[0], 2.0f);  // unaffected by the clone's calls
  copy.evaluate({g.data(), 1, 1}, out.view());
  EXPECT_EQ(out.fitness[0], 3.0f);  // a copy shares the original's instance
}

TEST(Task, ClonePreservesOptionalMembers) {
  const Task task{FullTask{}};
  const Task clone = task.clone();
  EXPECT_EQ(clone.name(), "toy");
  EXPECT_TRUE(clone.shareable());
  EXPECT_EQ(clone.qd_offset(), -5.0);
}

TEST(Task, EmptyBatchIsFine) {
  const Task task{MinimalTask{}};
  EvaluationBatch out;
  out.resize(0, 2);
  RowMatrix g(0, 3);
  EXPECT_NO_THROW(task.evaluate({g.data(), 0, 3}, out.view()));
}

TEST(Task, ViewsSliceRows) {
  RowMatrix g(4, 3);
  for (Index k = 0; k < g.size(); ++k) g.data()[k] = static_cast<Real>(k);
  const GenotypeView view{g.data(), 4, 3};
  EXPECT_EQ(view.row(2)[1], 7.0f);
  const GenotypeView tail = view.rows(1, 3);
  EXPECT_EQ(tail.count, 3);
  EXPECT_EQ(tail.row(0)[0], 3.0f);

  EvaluationBatch out;
  out.resize(4, 2);
  const EvaluationView ev = out.view().rows(2, 2);
  ev.fitness[0] = 9.0f;
  ev.base_row(1)[1] = 0.25f;
  ev.valid[1] = 1;
  EXPECT_EQ(out.fitness[2], 9.0f);
  EXPECT_EQ(out.base_features(3, 1), 0.25f);
  EXPECT_EQ(out.valid[3], 1);
  EXPECT_EQ(out.size(), 4);
}

// Throws its own exception (not a qdmeta::Error) on every row whose first gene is `marker`, after
// writing the rows before it, as a simulator that diverges on one controller does.
struct ThrowsOnMarker {
  Real marker = 0.5f;
  std::string name() const { return "diverges"; }
  Index genotype_size() const { return 1; }
  Index base_feature_size() const { return 1; }
  void evaluate(GenotypeView g, EvaluationView e) const {
    for (Index i = 0; i < g.count; ++i) {
      if (g.row(i)[0] == marker) throw std::runtime_error("simulator diverged");
      e.fitness[i] = 0;
      e.base_row(i)[0] = g.row(i)[0];
      e.valid[i] = 1;
    }
  }
};

// As ThrowsOnMarker, but its errors are its caller's business (as the Python module's tasks).
struct ThrowsOnMarkerItself : ThrowsOnMarker {
  static constexpr bool kOwnErrors = true;
};

RowMatrix genes_with_marker_at(Index rows, Index marked, Real marker) {
  RowMatrix g(rows, 1);
  for (Index r = 0; r < rows; ++r) g(r, 0) = r == marked ? marker : 0.25f;
  return g;
}

std::string message_of_failure(const Task& task, GenotypeView g) {
  EvaluationBatch out;
  out.resize(g.count, task.base_feature_size());
  try {
    task.evaluate(g, out.view());
  } catch (const TaskFailed& e) {
    return e.what();
  }
  return "no TaskFailed";
}

TEST(Task, AnExceptionOfTheTasksOwnNamesTheRowThatThrewAndNestsTheOriginal) {
  const Task task{ThrowsOnMarker{}};
  const RowMatrix g = genes_with_marker_at(40, 37, 0.5f);
  EvaluationBatch out;
  out.resize(40, 1);
  try {
    task.evaluate({g.data(), 40, 1}, out.view());
    FAIL() << "no exception";
  } catch (const TaskFailed& e) {
    EXPECT_STREQ(e.what(), "task 'diverges' threw on row 37 of the batch: simulator diverged");
    EXPECT_EQ(e.task(), "diverges");
    EXPECT_EQ(e.row(), 37);
    try {
      e.rethrow_nested();
    } catch (const std::runtime_error& original) {
      EXPECT_STREQ(original.what(), "simulator diverged");
    }
  }
}

TEST(Task, TheRowNamedIsTheBatchRowWhenTheTaskSeesABlockOfIt) {
  // An evaluator hands a task rows 32-39 of a batch of 40: the message names row 37, not 5.
  const Task task{ThrowsOnMarker{}};
  const RowMatrix g = genes_with_marker_at(40, 37, 0.5f);
  const GenotypeView batch{g.data(), 40, 1};
  EXPECT_EQ(message_of_failure(task, batch.rows(32, 8)), "task 'diverges' threw on row 37 of the batch: simulator diverged");
  EXPECT_EQ(message_of_failure(task, batch.rows(32, 8).rows(4, 4)),
            "task 'diverges' threw on row 37 of the batch: simulator diverged");
}

TEST(Task, ABadOutputNamesTheBatchRowToo) {
  BadTask bad;
  bad.fault = BadTask::Fault::kNanFitness;
  bad.bad_row = 2;
  const Task task{bad};
  RowMatrix g(10, 2);
  g.setConstant(0.5f);
  EvaluationBatch out;
  out.resize(4, 3);
  try {
    task.evaluate(GenotypeView{g.data(), 10, 2}.rows(6, 4), out.view());
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "task 'bad-task': fitness of solution 8 is nan");
  }
}

TEST(Task, AnExceptionThatIsNotAStdExceptionIsNamedToo) {
  struct ThrowsAnInt : MinimalTask {
    void evaluate(GenotypeView, EvaluationView) const { throw 42; }
  };
  const Task task{ThrowsAnInt{}};
  const RowMatrix g(1, 3);
  EXPECT_EQ(message_of_failure(task, {g.data(), 1, 3}),
            "task 'task' threw on row 0 of the batch: an exception that is not a std::exception");
}

TEST(Task, QdmetasOwnErrorsAndATaskThatKeepsItsErrorsPassUnchanged) {
  struct ThrowsInputError : MinimalTask {
    void evaluate(GenotypeView, EvaluationView) const { throw InputError("a bad key"); }
  };
  const RowMatrix g3(2, 3);
  EvaluationBatch out;
  out.resize(2, 2);
  try {
    Task{ThrowsInputError{}}.evaluate({g3.data(), 2, 3}, out.view());
    FAIL() << "no exception";
  } catch (const TaskFailed&) {
    FAIL() << "wrapped";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "a bad key");
  }
  const RowMatrix g = genes_with_marker_at(4, 1, 0.5f);
  out.resize(4, 1);
  try {
    Task{ThrowsOnMarkerItself{}}.evaluate({g.data(), 4, 1}, out.view());
    FAIL() << "no exception";
  } catch (const TaskFailed&) {
    FAIL() << "wrapped";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "simulator diverged");
  }
}

TEST(Task, RowsThatThrowOnlyTogetherAreNamedAsABlock) {
  // Throws when handed more than 3 rows at once: no row throws alone.
  struct ThrowsOnBigBlocks : MinimalTask {
    void evaluate(GenotypeView g, EvaluationView e) const {
      if (g.count > 3) throw std::runtime_error("out of scratch memory");
      MinimalTask::evaluate(g, e);
    }
  };
  const Task task{ThrowsOnBigBlocks{}};
  const RowMatrix g(20, 3);
  EXPECT_EQ(message_of_failure(task, GenotypeView{g.data(), 20, 3}.rows(10, 5)),
            "task 'task' threw on rows 10-14 of the batch (no row threw alone, or the search for it ran out of time): "
            "out of scratch memory");
}

}  // namespace
}  // namespace qdmeta
