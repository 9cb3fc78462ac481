#include "qdmeta/run/checkpoint.hpp"

#include <fmt/format.h>
#include <fmt/std.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "qdmeta/archive/elite_checks.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/regular_file.hpp"

namespace qdmeta {

namespace {
constexpr std::string_view kMagic{"QDMETA-CHECKPOINT\n", 18};

bool is_version(std::string_view v) {
  return !v.empty() && v.size() <= kMaxVersionBytes && std::all_of(v.begin(), v.end(), [](char c) {
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '.' || c == '+' || c == '-';
  });
}

// The version rule of checkpoint.hpp.
void check_version(std::string_view version, const std::string& source) {
  if (!is_version(version))
    throw InputError(fmt::format("{} is damaged: its program version is not a version ({} bytes)", source, version.size()));
  if (version == kVersion ||
      std::find(kCheckpointResumesFrom.begin(), kCheckpointResumesFrom.end(), version) != kCheckpointResumesFrom.end())
    return;
  throw InputError(fmt::format("{} was written by qdmeta {}, whose runs this qdmeta ({}) is not known to continue to the "
                               "same bits: finish it with qdmeta {}, or start it over",
                               source, version, kVersion, version));
}

}  // namespace

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
  head.value(cursor.metrics_hash);
  head.value(cursor.meta_hash);
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

  // The checksum closes the file and covers every byte before it, header included.
  std::string bytes;
  bytes.reserve(kMagic.size() + header.bytes().size() + payload.size() + sizeof(std::uint64_t));
  bytes.append(kMagic).append(header.bytes()).append(payload);
  BinaryWriter checksum;
  checksum.value(fnv1a64(bytes));
  bytes.append(checksum.bytes());

  AtomicFile file(dir / kCheckpointFile);
  file.write(bytes);
  file.commit();
}

RunCursor read_checkpoint(const std::filesystem::path& dir, std::uint64_t fingerprint, Algorithm& algorithm) {
  const std::filesystem::path path = dir / kCheckpointFile;
  if (!path_taken(path))
    throw InputError(fmt::format("no checkpoint in {} (a run writes one periodically and when stopped)", dir));
  const std::string bytes = read_regular_file(path, kMaxBinaryFileBytes);
  const std::string source = fmt::format("checkpoint {}", path);
  if (!std::string_view(bytes).starts_with(kMagic)) throw InputError(fmt::format("{} is not a qdmeta checkpoint", source));
  constexpr std::size_t kChecksumSize = sizeof(std::uint64_t);
  if (bytes.size() < kMagic.size() + sizeof(std::uint32_t) + kChecksumSize)
    throw InputError(fmt::format("{} is damaged: only {} bytes", source, bytes.size()));
  // The format first (an older file says so rather than "damaged"), then the whole-file checksum
  // before any other field is trusted.
  const auto format = BinaryReader(std::string_view(bytes).substr(kMagic.size(), sizeof(std::uint32_t)), source)
                          .value<std::uint32_t>("format version");
  if (format != kCheckpointFormat)
    throw InputError(fmt::format("{} has format {}, this qdmeta ({}) reads format {}", source, format, kVersion,
                                 kCheckpointFormat));
  const std::string_view body = std::string_view(bytes).substr(0, bytes.size() - kChecksumSize);
  const auto stored = BinaryReader(std::string_view(bytes).substr(body.size()), source).value<std::uint64_t>("checksum");
  if (fnv1a64(body) != stored) throw InputError(fmt::format("{} is damaged: checksum mismatch", source));

  BinaryReader r(body.substr(kMagic.size() + sizeof(std::uint32_t)), source);
  check_version(r.string("program version"), source);
  const std::string name = r.string("algorithm name");
  if (name != algorithm.name())
    throw InputError(fmt::format("{} was written by algorithm '{}', but config.toml now builds '{}'", source, name,
                                 algorithm.name()));
  if (r.value<std::uint64_t>("config fingerprint") != fingerprint)
    throw InputError(fmt::format("{} was written for a different configuration: config.toml changed since", source));
  const auto size = r.value<std::uint64_t>("payload size");
  if (size != r.remaining())
    throw InputError(fmt::format("{} is damaged: {} payload bytes, the header says {}", source, r.remaining(), size));
  const std::string_view payload = body.substr(body.size() - size);

  BinaryReader p(payload, source);
  p.expect_tag("run");
  RunCursor c;
  c.next_log = p.value<std::int64_t>("next log");
  c.last_logged_generation = p.value<std::int64_t>("last logged generation");
  c.metrics_bytes = p.value<std::uint64_t>("metrics.csv length");
  c.meta_bytes = p.value<std::uint64_t>("meta.csv length");
  c.metrics_hash = p.value<std::uint64_t>("metrics.csv hash");
  c.meta_hash = p.value<std::uint64_t>("meta.csv hash");
  c.wall_seconds = p.value<double>("wall seconds");
  c.checkpoints = p.value<std::int64_t>("checkpoint count");
  algorithm.load(p);
  p.expect_tag("end");
  p.finish();
  check_restored_elites(algorithm.elites(), source);
  return c;
}

}  // namespace qdmeta
