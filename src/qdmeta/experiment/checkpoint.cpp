#include "qdmeta/experiment/checkpoint.hpp"

#include <fmt/format.h>
#include <fmt/std.h>

#include <fstream>
#include <sstream>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/io/atomic_file.hpp"

namespace qdmeta {

namespace {
constexpr std::string_view kMagic{"QDMETA-CHECKPOINT\n", 18};
}

std::uint64_t config_fingerprint(const toml::table& resolved) {
  toml::table copy = resolved;
  copy.erase("provenance");
  std::ostringstream text;
  text << copy;
  return fnv1a64(text.str());
}

RunSnapshot take_snapshot(const RunCursor& cursor, const Algorithm& algorithm) {
  BinaryWriter state;
  algorithm.save(state);
  return {cursor, algorithm.name(), state.bytes()};
}

void write_checkpoint(const std::filesystem::path& dir, std::uint64_t fingerprint, const RunCursor& cursor,
                      const Algorithm& algorithm) {
  write_checkpoint(dir, fingerprint, take_snapshot(cursor, algorithm));
}

void write_checkpoint(const std::filesystem::path& dir, std::uint64_t fingerprint, const RunSnapshot& snapshot) {
  const RunCursor& cursor = snapshot.cursor;
  BinaryWriter head;
  head.tag("run");
  head.value(cursor.next_log);
  head.value(cursor.last_logged_generation);
  head.value(cursor.metrics_bytes);
  head.value(cursor.meta_bytes);
  head.value(cursor.wall_seconds);
  head.value(cursor.checkpoints);
  BinaryWriter tail;
  tail.tag("end");
  const std::string payload = head.bytes() + snapshot.algorithm_state + tail.bytes();

  BinaryWriter header;
  header.value<std::uint32_t>(kCheckpointFormat);
  header.string(kVersion);
  header.string(snapshot.algorithm_name);
  header.value(fingerprint);
  header.value<std::uint64_t>(payload.size());
  header.value(fnv1a64(payload));

  AtomicFile file(dir / kCheckpointFile);
  file.stream().write(kMagic.data(), static_cast<std::streamsize>(kMagic.size()));
  file.stream().write(header.bytes().data(), static_cast<std::streamsize>(header.bytes().size()));
  file.stream().write(payload.data(), static_cast<std::streamsize>(payload.size()));
  file.commit();
}

RunCursor read_checkpoint(const std::filesystem::path& dir, std::uint64_t fingerprint, Algorithm& algorithm) {
  const std::filesystem::path path = dir / kCheckpointFile;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("no checkpoint in {} (a run writes one periodically and when stopped)", dir));
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::string source = fmt::format("checkpoint {}", path);
  if (!std::string_view(bytes).starts_with(kMagic)) throw InputError(fmt::format("{} is not a qdmeta checkpoint", source));
  BinaryReader r(std::string_view(bytes).substr(kMagic.size()), source);
  const auto format = r.value<std::uint32_t>("format version");
  if (format != kCheckpointFormat)
    throw InputError(fmt::format("{} has format {}, this qdmeta ({}) reads format {}", source, format, kVersion,
                                 kCheckpointFormat));
  const std::string version = r.string("program version");
  const std::string name = r.string("algorithm name");
  if (name != algorithm.name())
    throw InputError(fmt::format("{} was written by algorithm '{}', but config.toml now builds '{}'", source, name,
                                 algorithm.name()));
  if (r.value<std::uint64_t>("config fingerprint") != fingerprint)
    throw InputError(fmt::format("{} was written for a different configuration: config.toml changed since", source));
  const auto size = r.value<std::uint64_t>("payload size");
  const auto checksum = r.value<std::uint64_t>("payload checksum");
  if (size != r.remaining())
    throw InputError(fmt::format("{} is damaged: {} payload bytes, the header says {}", source, r.remaining(), size));
  const std::string_view payload = std::string_view(bytes).substr(bytes.size() - size);
  if (fnv1a64(payload) != checksum) throw InputError(fmt::format("{} is damaged: checksum mismatch", source));
  (void)version;

  BinaryReader p(payload, source);
  p.expect_tag("run");
  RunCursor c;
  c.next_log = p.value<std::int64_t>("next log");
  c.last_logged_generation = p.value<std::int64_t>("last logged generation");
  c.metrics_bytes = p.value<std::uint64_t>("metrics.csv length");
  c.meta_bytes = p.value<std::uint64_t>("meta.csv length");
  c.wall_seconds = p.value<double>("wall seconds");
  c.checkpoints = p.value<std::int64_t>("checkpoint count");
  algorithm.load(p);
  p.expect_tag("end");
  p.finish();
  return c;
}

}  // namespace qdmeta
