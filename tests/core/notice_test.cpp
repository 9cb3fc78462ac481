// Tests of src/qdmeta/core/notice.{hpp,cpp}: the library's notices go to the sink a program sets,
// and without one nowhere (never to stderr).
#include "qdmeta/core/notice.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace qdmeta {
namespace {

// Installs `sink` for one test, then puts back what was there.
class ScopedSink {
 public:
  explicit ScopedSink(NoticeSink sink) : previous_(set_notice_sink(std::move(sink))) {}
  ~ScopedSink() { set_notice_sink(std::move(previous_)); }
  ScopedSink(const ScopedSink&) = delete;
  ScopedSink& operator=(const ScopedSink&) = delete;

 private:
  NoticeSink previous_;
};

TEST(Notice, WithoutASinkNothingIsWritten) {
  const ScopedSink none{NoticeSink{}};
  EXPECT_FALSE(has_notice_sink());
  testing::internal::CaptureStderr();
  notice(NoticeKind::kWarning, "unheard");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(Notice, TheSinkHearsKindAndTextAndIsReplacedInTurn) {
  std::vector<std::pair<NoticeKind, std::string>> heard;
  const ScopedSink mine{[&](NoticeKind kind, const std::string& text) { heard.emplace_back(kind, text); }};
  EXPECT_TRUE(has_notice_sink());
  notice(NoticeKind::kInformation, "k-means: this can take minutes");
  notice(NoticeKind::kWarning, "a warning");
  ASSERT_EQ(heard.size(), 2u);
  EXPECT_EQ(heard[0], std::make_pair(NoticeKind::kInformation, std::string("k-means: this can take minutes")));
  EXPECT_EQ(heard[1], std::make_pair(NoticeKind::kWarning, std::string("a warning")));
  // set_notice_sink hands back the sink it replaces.
  NoticeSink previous = set_notice_sink({});
  ASSERT_TRUE(previous);
  previous(NoticeKind::kInformation, "through the returned sink");
  EXPECT_EQ(heard.back().second, "through the returned sink");
  notice(NoticeKind::kInformation, "dropped");
  EXPECT_EQ(heard.size(), 3u);
  set_notice_sink(std::move(previous));
}

TEST(Notice, ASinkThatThrowsDoesNotFailTheWork) {
  const ScopedSink throwing{[](NoticeKind, const std::string&) { throw std::runtime_error("sink broke"); }};
  EXPECT_NO_THROW(notice(NoticeKind::kWarning, "x"));
}

TEST(Notice, TheCommandLinesSinkPrintsOneLineNamingTheProgram) {
  testing::internal::CaptureStderr();
  print_notice_to_stderr(NoticeKind::kInformation, "CVT points: 256 valid");
  print_notice_to_stderr(NoticeKind::kWarning, "cache unreadable");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "qdmeta: CVT points: 256 valid\nqdmeta: warning: cache unreadable\n");
}

}  // namespace
}  // namespace qdmeta
