#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>

namespace terramesh::datasets::internal {

/// The whole content of a file.
/// @throw terramesh::InputError if the file cannot be opened or read.
std::string readWholeFile(const std::filesystem::path& path);

/// Decodes a little-endian integer or IEEE float from `bytes` (any host byte order).
template <class T>
T loadLittleEndian(const unsigned char* bytes) {
  static_assert(std::is_arithmetic_v<T> &&
                (sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4 || sizeof(T) == 8));
  using Bits = std::conditional_t<
      sizeof(T) == 1, std::uint8_t,
      std::conditional_t<sizeof(T) == 2, std::uint16_t,
                         std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
  Bits bits = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) bits |= static_cast<Bits>(Bits{bytes[i]} << (8 * i));
  T value;
  std::memcpy(&value, &bits, sizeof(T));
  return value;
}

/// Reads little-endian records from a file held in memory; running past the end or a bad value
/// becomes terramesh::InputError naming the file, the byte offset, the record and the field.
class BinaryCursor {
 public:
  /// @throw terramesh::InputError if the file cannot be opened or read.
  explicit BinaryCursor(const std::filesystem::path& path);

  /// Names the record being read, for error messages (e.g. "image 3 of 40").
  void setRecord(std::string record) { record_ = std::move(record); }

  /// @throw terramesh::InputError if fewer than `count` bytes are left.
  void require(std::size_t count, std::string_view what) const;
  /// Whether at least `count` bytes are left.
  bool has(std::size_t count) const { return bytes_.size() - offset_ >= count; }

  template <class T>
  T read(const char* field) {
    require(sizeof(T), field);
    const T value =
        loadLittleEndian<T>(reinterpret_cast<const unsigned char*>(bytes_.data() + offset_));
    offset_ += sizeof(T);
    return value;
  }
  /// A float64 that must be finite.
  /// @throw terramesh::InputError naming the value's offset otherwise.
  double readFinite(const char* field);
  /// A NUL-terminated string.
  /// @throw terramesh::InputError if the file ends before the NUL.
  std::string readCString(const char* field);

  /// A count of records of at least `min_record_bytes` each, checked against the bytes left, so
  /// that a corrupt count fails here rather than in an allocation.
  /// @throw terramesh::InputError if the file cannot hold that many records.
  std::uint64_t readCount(const char* field, std::size_t min_record_bytes);

  /// @throw terramesh::InputError if bytes are left after the last record.
  void expectEnd(const std::string& what) const;

  /// @throw terramesh::InputError naming the file, `offset` and the current record.
  [[noreturn]] void fail(std::size_t offset, const std::string& problem) const;

  std::size_t offset() const { return offset_; }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::string bytes_;
  std::size_t offset_ = 0;
  std::string record_;
};

}  // namespace terramesh::datasets::internal
