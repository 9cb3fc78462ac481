#include "qdmeta/core/notice.hpp"

#include "qdmeta/core/one_line.hpp"

#include <cstdio>
#include <memory>
#include <mutex>
#include <utility>

namespace qdmeta {
namespace {

std::mutex g_mutex;
// Shared, so that a notice being delivered keeps its sink alive while another thread replaces it.
std::shared_ptr<const NoticeSink> g_sink;

}  // namespace

NoticeSink set_notice_sink(NoticeSink sink) {
  auto next = sink ? std::make_shared<const NoticeSink>(std::move(sink)) : nullptr;
  const std::lock_guard lock(g_mutex);
  NoticeSink previous = g_sink ? *g_sink : NoticeSink{};
  g_sink = std::move(next);
  return previous;
}

bool has_notice_sink() {
  const std::lock_guard lock(g_mutex);
  return g_sink != nullptr;
}

void notice(NoticeKind kind, const std::string& text) {
  std::shared_ptr<const NoticeSink> sink;
  {
    const std::lock_guard lock(g_mutex);
    sink = g_sink;
  }
  if (!sink) return;
  try {
    (*sink)(kind, text);
  } catch (...) {  // a notice is never worth failing the work it describes
  }
}

void print_notice_to_stderr(NoticeKind kind, const std::string& text) {
  std::fprintf(stderr, "qdmeta: %s%s\n", kind == NoticeKind::kWarning ? "warning: " : "",
               one_line(text).c_str());
  std::fflush(stderr);
}

}  // namespace qdmeta
