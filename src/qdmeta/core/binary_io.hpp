#pragma once
// Little binary streams for checkpoints: every stateful component writes itself to a
// BinaryWriter and reads itself back from a BinaryReader in the same order. Reads are checked:
// a truncated or misaligned stream throws InputError naming the source and what was expected,
// never returns garbage. Named tags between sections catch a reader and writer out of step.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "qdmeta/core/eigen.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

// FNV-1a, 64 bits: the checkpoint's checksum, the config fingerprint and the logs' prefixes.
// `h` continues a hash: fnv1a64(b, fnv1a64(a)) == fnv1a64(a + b).
inline constexpr std::uint64_t kFnv1a64Basis = 0xcbf29ce484222325ULL;
std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = kFnv1a64Basis);

class BinaryWriter {
 public:
  template <class T>
    requires std::is_arithmetic_v<T>
  void value(T x) {
    const auto* p = reinterpret_cast<const char*>(&x);
    bytes_.append(p, sizeof x);
  }
  void boolean(bool b) { value<std::uint8_t>(b ? 1 : 0); }
  void string(std::string_view s) {
    value<std::uint64_t>(s.size());
    bytes_.append(s);
  }
  void tag(std::string_view name) { string(name); }
  template <class T>
    requires std::is_arithmetic_v<T>
  void values(const std::vector<T>& v) {
    value<std::uint64_t>(v.size());
    raw(v.data(), v.size() * sizeof(T));
  }
  // Any dense Eigen matrix or vector, with its shape.
  template <class Derived>
  void matrix(const Eigen::DenseBase<Derived>& m) {
    using Scalar = typename Derived::Scalar;
    value<std::int64_t>(m.rows());
    value<std::int64_t>(m.cols());
    const typename Derived::PlainObject plain = m;  // contiguous, in the matrix's own order
    raw(plain.data(), static_cast<std::size_t>(plain.size()) * sizeof(Scalar));
  }
  const std::string& bytes() const { return bytes_; }

 private:
  void raw(const void* p, std::size_t n) { bytes_.append(static_cast<const char*>(p), n); }
  std::string bytes_;
};

class BinaryReader {
 public:
  // `source` names the stream in messages (e.g. the checkpoint's path).
  BinaryReader(std::string_view bytes, std::string source) : bytes_(bytes), source_(std::move(source)) {}

  template <class T>
    requires std::is_arithmetic_v<T>
  T value(std::string_view what) {
    T x;
    std::memcpy(&x, take(sizeof x, what), sizeof x);
    return x;
  }
  bool boolean(std::string_view what) { return value<std::uint8_t>(what) != 0; }
  std::string string(std::string_view what);
  // Reads a tag and throws unless it is `name`.
  void expect_tag(std::string_view name);
  template <class T>
    requires std::is_arithmetic_v<T>
  std::vector<T> values(std::string_view what) {
    const auto n = count(what, sizeof(T));
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), take(n * sizeof(T), what), n * sizeof(T));
    return v;
  }
  // Reads a matrix written by BinaryWriter::matrix into `m` (resized to the stored shape).
  template <class Derived>
  void matrix(Eigen::PlainObjectBase<Derived>& m, std::string_view what) {
    using Scalar = typename Derived::Scalar;
    const auto rows = value<std::int64_t>(what);
    const auto cols = value<std::int64_t>(what);
    check_shape(rows, cols, sizeof(Scalar), what);
    m.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    const std::size_t n = static_cast<std::size_t>(rows * cols) * sizeof(Scalar);
    if (n) std::memcpy(m.data(), take(n, what), n);
  }
  std::size_t remaining() const { return bytes_.size() - position_; }
  // Throws unless every byte was read.
  void finish() const;
  const std::string& source() const { return source_; }
  [[noreturn]] void fail(std::string_view message) const;

 private:
  const char* take(std::size_t n, std::string_view what);
  std::size_t count(std::string_view what, std::size_t element_size);
  void check_shape(std::int64_t rows, std::int64_t cols, std::size_t element_size, std::string_view what) const;

  std::string_view bytes_;
  std::string source_;
  std::size_t position_ = 0;
};

}  // namespace qdmeta
