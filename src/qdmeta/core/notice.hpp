#pragma once
// What the library has to tell a person that is not an error: a long computation starting
// (CVT's k-means), a count worth knowing, a warning. The library never writes to stderr itself:
// a program chooses where notices go. The qdmeta command and the Python module print them to
// stderr as "qdmeta: <text>" and "qdmeta: warning: <text>"; a program that sets no sink drops them.
#include <functional>
#include <string>

namespace qdmeta {

enum class NoticeKind { kInformation, kWarning };

using NoticeSink = std::function<void(NoticeKind kind, const std::string& text)>;

// Sends later notices to `sink` (empty: nowhere) and returns the sink it replaces. Thread-safe.
NoticeSink set_notice_sink(NoticeSink sink);
// True when a sink is set.
bool has_notice_sink();
// Passes `text` to the sink, if any. Thread-safe; a sink that throws is ignored.
void notice(NoticeKind kind, const std::string& text);
// The sink of the qdmeta command: one line on stderr, "qdmeta: " (and "warning: ") before the text.
void print_notice_to_stderr(NoticeKind kind, const std::string& text);

}  // namespace qdmeta
