#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

/// A small, generic PLY reader and writer (http://paulbourke.net/dataformats/ply/): elements with
/// named, typed scalar properties and list properties; reads ascii, binary little-endian and
/// binary big-endian; writes all three. Values are held as double, which represents every PLY
/// type (8 to 32 bit integers, float, double) exactly. Not thread-safe per document.
namespace terramesh::ply {

/// A PLY scalar type. The header names both the classic ("uchar") and the sized ("uint8")
/// spellings; the writer emits the classic ones, which every viewer reads.
enum class Type { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

enum class Format { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

/// Size in bytes of one value of `type`.
std::size_t sizeOf(Type type);
/// The classic PLY name ("char", "uchar", "short", "ushort", "int", "uint", "float", "double").
const char* nameOf(Type type);
/// Parses either spelling of a type name; nullopt if unknown.
std::optional<Type> parseType(const std::string& name);

/// One property of an element: a scalar (one value per item) or a list (a variable number of
/// values per item, e.g. a face's vertex indices).
struct Property {
  std::string name;
  Type type = Type::kFloat32;  ///< scalar type, or the type of the list's items
  /// Set for list properties: the type of the per-item count.
  std::optional<Type> list_count_type;
  /// Scalars: one value per item. Lists: every item's values, concatenated.
  std::vector<double> values;
  /// Lists only: item i holds values[list_offsets[i] .. list_offsets[i + 1]); size count + 1.
  std::vector<std::size_t> list_offsets;

  bool isList() const { return list_count_type.has_value(); }
  /// Number of values of list item `item`. @pre isList().
  std::size_t listSize(std::size_t item) const { return list_offsets[item + 1] - list_offsets[item]; }
};

/// A named element ("vertex", "face", ...) with `count` items.
struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;

  /// The property called `name`, or nullptr.
  const Property* find(const std::string& property_name) const;
  Property* find(const std::string& property_name);
  /// Appends an empty scalar property (fill `values` with `count` values). Adding a property may
  /// move the others: fill each before adding the next, or look them up again with find().
  Property& addScalar(const std::string& property_name, Type type);
  /// Appends an empty list property (fill `values` and `list_offsets`).
  Property& addList(const std::string& property_name, Type count_type, Type item_type);
};

/// A whole PLY file.
struct Document {
  Format format = Format::kBinaryLittleEndian;  ///< as read; write() takes its own format
  std::vector<std::string> comments;
  std::vector<Element> elements;

  const Element* find(const std::string& element_name) const;
  Element* find(const std::string& element_name);
  /// Appends an element with `count` items and no properties yet (may move the other elements).
  Element& addElement(const std::string& element_name, std::size_t count);
};

/// Called by read() after each item of an element is read, with that item's values (and every
/// earlier item's) in place: lets a caller validate items in file order, so that the first bad
/// item is the one reported even when the file is also truncated later. It reports by throwing.
using ItemCheck = std::function<void(const Element& element, std::size_t item)>;

/// Reads a PLY file. Elements and properties keep the file's order.
/// @throw terramesh::InputError naming the file and the header line ("line 7") or the element
///        item ("face 12") and what was expected (bad magic, unknown format or type, truncated
///        data, malformed ascii numbers, negative list counts); whatever `check` throws.
Document read(const std::filesystem::path& path, const ItemCheck& check = {});
/// Same, from a stream opened in binary mode; `file_name` is used in error messages.
Document read(std::istream& in, const std::string& file_name, const ItemCheck& check = {});

/// Writes `document` in `format` (ascii numbers with full precision, "nan"/"inf" for non-finite
/// floats). Values are converted to each property's type: integers are rounded and clamped to
/// the type's range (NaN becomes 0).
/// @throw std::invalid_argument if a property's value count does not match its element's count.
void write(std::ostream& out, const Document& document, Format format);
/// Writes atomically (temp file + rename, see common/atomic_file.h).
/// @throw std::invalid_argument as write(); std::runtime_error if the file cannot be written.
void writeFile(const std::filesystem::path& path, const Document& document, Format format);

}  // namespace terramesh::ply
