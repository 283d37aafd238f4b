#pragma once
// Little-endian byte buffers for checkpoints: a writer that appends fields to a string, and a
// bounds-checked reader that reports any problem as terramesh::InputError naming the file, the
// byte offset and the section being read.

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "common/input_error.h"

namespace terramesh::mesher::internal {

/// FNV-1a, 64 bits, over `size` bytes.
inline std::uint64_t fnv1a64(const char* data, std::size_t size) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= static_cast<unsigned char>(data[i]);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

class ByteWriter {
 public:
  template <class T>
  void pod(const T& value) {
    static_assert(std::is_arithmetic_v<T>, "write fields one by one (no padding bytes)");
    const std::size_t at = buffer_.size();
    buffer_.resize(at + sizeof(T));
    std::memcpy(&buffer_[at], &value, sizeof(T));
  }
  void u8(std::uint8_t v) { pod(v); }
  void u32(std::uint32_t v) { pod(v); }
  void u64(std::uint64_t v) { pod(v); }
  void f64(double v) { pod(v); }
  template <class T>
  void vector(const std::vector<T>& values) {
    u64(values.size());
    for (const T& v : values) pod(v);
  }
  void string(const std::string& text) {
    u64(text.size());
    buffer_.append(text);
  }
  const std::string& buffer() const { return buffer_; }

 private:
  std::string buffer_;
};

class ByteReader {
 public:
  ByteReader(const std::string& data, std::string file, std::size_t base_offset)
      : data_(data), file_(std::move(file)), base_(base_offset) {}

  /// Names the part being read, for error messages.
  void section(const char* name) { section_ = name; }

  template <class T>
  T pod() {
    static_assert(std::is_arithmetic_v<T>);
    need(sizeof(T));
    T value;
    std::memcpy(&value, data_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  std::uint8_t u8() { return pod<std::uint8_t>(); }
  std::uint32_t u32() { return pod<std::uint32_t>(); }
  std::uint64_t u64() { return pod<std::uint64_t>(); }
  double f64() { return pod<double>(); }
  bool flag() {
    const std::uint8_t v = u8();
    if (v > 1) fail("a boolean (0 or 1), got " + std::to_string(v));
    return v == 1;
  }

  /// Reads an element count and checks that `count * min_element_bytes` bytes remain, so a corrupt
  /// count can never make the caller allocate more than the file holds.
  std::size_t count(std::size_t min_element_bytes) {
    const std::uint64_t n = u64();
    if (min_element_bytes > 0 && n > (data_.size() - at_) / min_element_bytes) {
      fail("a count of " + std::to_string(n) + " elements, more than the remaining " +
           std::to_string(data_.size() - at_) + " bytes can hold");
    }
    return static_cast<std::size_t>(n);
  }
  template <class T>
  std::vector<T> vector() {
    std::vector<T> values(count(sizeof(T)));
    for (T& v : values) v = pod<T>();
    return values;
  }
  std::string string() {
    const std::size_t n = count(1);
    std::string text = data_.substr(at_, n);
    at_ += n;
    return text;
  }
  /// An index that must be below `limit` (or equal to `none` when `none` is given).
  std::uint32_t index(std::size_t limit, const char* what, bool allow_none = false) {
    const std::uint32_t i = u32();
    if (allow_none && i == std::numeric_limits<std::uint32_t>::max()) return i;
    if (i >= limit) fail(std::string(what) + " index below " + std::to_string(limit) + ", got " + std::to_string(i));
    return i;
  }
  bool atEnd() const { return at_ == data_.size(); }

  [[noreturn]] void fail(const std::string& expected) const {
    throw InputError(file_, "byte " + std::to_string(base_ + at_) + " (" + section_ + ")",
                     "corrupt checkpoint: expected " + expected);
  }

 private:
  void need(std::size_t bytes) const {
    if (data_.size() - at_ < bytes) fail(std::to_string(bytes) + " more bytes, the payload ends");
  }

  const std::string& data_;
  std::string file_;
  std::size_t base_;
  std::size_t at_ = 0;
  std::string section_ = "payload";
};

}  // namespace terramesh::mesher::internal
