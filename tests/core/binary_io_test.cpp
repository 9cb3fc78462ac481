// Checkpoint streams: what is written reads back bit for bit, and a damaged or misaligned
// stream fails with a message instead of returning garbage.
#include "qdmeta/core/binary_io.hpp"

#include <gtest/gtest.h>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

TEST(BinaryIo, RoundTripsEveryKind) {
  BinaryWriter w;
  RowMatrix floats(3, 2);
  floats << 1.5f, -2.0f, 3.25f, 0.0f, -0.0f, 1e-30f;
  Eigen::MatrixXd doubles(2, 3);
  doubles << 1, 2, 3, 4, 5, 6;  // column-major: a different memory order
  Eigen::VectorXd vector(4);
  vector << 0.1, 0.2, 0.3, 0.4;
  w.tag("start");
  w.value<std::int64_t>(-42);
  w.value(3.141592653589793);
  w.boolean(true);
  w.string("hello");
  w.values(std::vector<float>{1.0f, 2.0f});
  w.values(std::vector<double>{});
  w.matrix(floats);
  w.matrix(doubles);
  w.matrix(vector);
  w.matrix(RowMatrix(0, 5));

  BinaryReader r(w.bytes(), "test stream");
  r.expect_tag("start");
  EXPECT_EQ(r.value<std::int64_t>("i"), -42);
  EXPECT_EQ(r.value<double>("d"), 3.141592653589793);
  EXPECT_TRUE(r.boolean("b"));
  EXPECT_EQ(r.string("s"), "hello");
  EXPECT_EQ(r.values<float>("v"), (std::vector<float>{1.0f, 2.0f}));
  EXPECT_TRUE(r.values<double>("e").empty());
  RowMatrix f;
  Eigen::MatrixXd d;
  Eigen::VectorXd v;
  RowMatrix empty;
  r.matrix(f, "f");
  r.matrix(d, "d");
  r.matrix(v, "v");
  r.matrix(empty, "empty");
  EXPECT_TRUE(f == floats);
  EXPECT_TRUE(d == doubles);
  EXPECT_TRUE(v == vector);
  EXPECT_EQ(empty.rows(), 0);
  EXPECT_EQ(empty.cols(), 5);
  r.finish();
}

TEST(BinaryIo, TruncationMisalignmentAndLeftoversAreErrors) {
  BinaryWriter w;
  w.tag("archive");
  w.values(std::vector<double>{1, 2, 3});
  const std::string& bytes = w.bytes();
  {
    BinaryReader r(std::string_view(bytes).substr(0, bytes.size() - 4), "cut");
    r.expect_tag("archive");
    EXPECT_THROW(r.values<double>("numbers"), InputError);
  }
  {
    BinaryReader r(bytes, "misaligned");
    try {
      r.expect_tag("database");
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("misaligned: expected section 'database'"), std::string::npos) << e.what();
    }
  }
  {
    BinaryReader r(bytes, "leftovers");
    r.expect_tag("archive");
    EXPECT_THROW(r.finish(), InputError);
  }
  {
    // A length field larger than the stream must not allocate or read past the end.
    BinaryWriter huge;
    huge.value<std::uint64_t>(1ULL << 60);
    BinaryReader r(huge.bytes(), "huge");
    EXPECT_THROW(r.values<double>("numbers"), InputError);
  }
}

TEST(BinaryIo, Fnv1aMatchesPublishedVectors) {
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ULL);
}

}  // namespace
}  // namespace qdmeta
