#include "common/ply.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <istream>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/input_error.h"

namespace terramesh::ply {
namespace {

constexpr bool kHostLittleEndian = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__;
// Items reserved up front at most: a header's count is untrusted, so a corrupt count ends in
// "file truncated" rather than in a huge allocation; larger elements grow as they are read.
constexpr std::size_t kMaxReservedItems = std::size_t{1} << 20;
constexpr std::size_t kMaxListLength = std::size_t{1} << 31;

bool isFloat(Type type) { return type == Type::kFloat32 || type == Type::kFloat64; }

double typeMin(Type type) {
  switch (type) {
    case Type::kInt8: return std::numeric_limits<std::int8_t>::min();
    case Type::kInt16: return std::numeric_limits<std::int16_t>::min();
    case Type::kInt32: return std::numeric_limits<std::int32_t>::min();
    default: return 0;
  }
}

double typeMax(Type type) {
  switch (type) {
    case Type::kInt8: return std::numeric_limits<std::int8_t>::max();
    case Type::kUInt8: return std::numeric_limits<std::uint8_t>::max();
    case Type::kInt16: return std::numeric_limits<std::int16_t>::max();
    case Type::kUInt16: return std::numeric_limits<std::uint16_t>::max();
    case Type::kInt32: return std::numeric_limits<std::int32_t>::max();
    case Type::kUInt32: return std::numeric_limits<std::uint32_t>::max();
    default: return std::numeric_limits<double>::max();
  }
}

/// Rounds and clamps an integer value into range; NaN becomes 0.
double toIntegerValue(double value, Type type) {
  if (std::isnan(value)) return 0;
  return std::clamp(std::round(value), typeMin(type), typeMax(type));
}

template <class T>
double decodeAs(const unsigned char* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return static_cast<double>(value);
}

double decode(Type type, const unsigned char* bytes) {
  switch (type) {
    case Type::kInt8: return decodeAs<std::int8_t>(bytes);
    case Type::kUInt8: return decodeAs<std::uint8_t>(bytes);
    case Type::kInt16: return decodeAs<std::int16_t>(bytes);
    case Type::kUInt16: return decodeAs<std::uint16_t>(bytes);
    case Type::kInt32: return decodeAs<std::int32_t>(bytes);
    case Type::kUInt32: return decodeAs<std::uint32_t>(bytes);
    case Type::kFloat32: return decodeAs<float>(bytes);
    case Type::kFloat64: return decodeAs<double>(bytes);
  }
  return 0;
}

template <class T>
void encodeAs(double value, unsigned char* bytes) {
  const T typed = static_cast<T>(value);
  std::memcpy(bytes, &typed, sizeof(T));
}

void encode(Type type, double value, unsigned char* bytes) {
  if (!isFloat(type)) value = toIntegerValue(value, type);
  switch (type) {
    case Type::kInt8: encodeAs<std::int8_t>(value, bytes); break;
    case Type::kUInt8: encodeAs<std::uint8_t>(value, bytes); break;
    case Type::kInt16: encodeAs<std::int16_t>(value, bytes); break;
    case Type::kUInt16: encodeAs<std::uint16_t>(value, bytes); break;
    case Type::kInt32: encodeAs<std::int32_t>(value, bytes); break;
    case Type::kUInt32: encodeAs<std::uint32_t>(value, bytes); break;
    case Type::kFloat32: encodeAs<float>(value, bytes); break;
    case Type::kFloat64: encodeAs<double>(value, bytes); break;
  }
}

class Reader {
 public:
  Reader(std::istream& in, std::string file, const ItemCheck& check) : in_(in), file_(std::move(file)), check_(check) {}

  Document read() {
    readHeader();
    for (Element& element : document_.elements) readElement(element);
    return std::move(document_);
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
    throw InputError(file_, where, problem);
  }

  Type typeAt(const std::string& name, std::size_t line) const {
    const std::optional<Type> type = parseType(name);
    if (!type) fail(lineLocation(line), "unknown PLY type \"" + name + "\"");
    return *type;
  }

  void readHeader() {
    std::string line;
    std::size_t line_number = 0;
    const auto next = [&]() {
      if (!std::getline(in_, line)) fail(lineLocation(line_number + 1), "PLY header ends before end_header");
      ++line_number;
      if (!line.empty() && line.back() == '\r') line.pop_back();
    };
    next();
    if (line != "ply") fail("line 1", "expected \"ply\" (not a PLY file)");
    bool have_format = false;
    while (true) {
      next();
      std::istringstream words(line);
      std::string keyword;
      words >> keyword;
      if (keyword == "end_header") break;
      if (keyword == "format") {
        std::string format, version;
        words >> format >> version;
        if (format == "ascii") document_.format = Format::kAscii;
        else if (format == "binary_little_endian") document_.format = Format::kBinaryLittleEndian;
        else if (format == "binary_big_endian") document_.format = Format::kBinaryBigEndian;
        else fail(lineLocation(line_number), "unknown PLY format \"" + format + "\"");
        have_format = true;
      } else if (keyword == "element") {
        std::string name;
        long long count = -1;
        if (!(words >> name >> count) || count < 0) {
          fail(lineLocation(line_number), "expected \"element NAME COUNT\"");
        }
        document_.addElement(name, static_cast<std::size_t>(count));
      } else if (keyword == "property") {
        if (document_.elements.empty()) fail(lineLocation(line_number), "property before any element");
        std::string type, name;
        words >> type;
        Element& element = document_.elements.back();
        if (type == "list") {
          std::string count_type, item_type;
          if (!(words >> count_type >> item_type >> name)) {
            fail(lineLocation(line_number), "expected \"property list COUNT_TYPE ITEM_TYPE NAME\"");
          }
          const Type count = typeAt(count_type, line_number);
          if (isFloat(count)) fail(lineLocation(line_number), "list count type must be an integer type");
          element.addList(name, count, typeAt(item_type, line_number));
        } else {
          if (!(words >> name)) fail(lineLocation(line_number), "expected \"property TYPE NAME\"");
          element.addScalar(name, typeAt(type, line_number));
        }
      } else if (keyword == "comment") {
        const std::size_t start = line.find("comment") + 7;
        document_.comments.push_back(start < line.size() ? line.substr(start + 1) : "");
      } else if (keyword != "obj_info" && !keyword.empty()) {
        fail(lineLocation(line_number), "unexpected header line \"" + line + "\"");
      }
    }
    if (!have_format) fail("header", "missing \"format\" line");
  }

  /// "face 12": where item `item` of `element` is, for messages (built only on failure).
  static std::string itemLocation(const Element& element, std::size_t item) {
    return element.name + " " + std::to_string(item);
  }

  double readValue(Type type, const Element& element, std::size_t item) {
    if (document_.format == Format::kAscii) {
      if (!(in_ >> token_)) fail(itemLocation(element, item), "expected a number, the file ends early");
      const char* begin = token_.c_str();
      char* end = nullptr;
      const double value = std::strtod(begin, &end);
      if (end == begin || *end != '\0') {
        fail(itemLocation(element, item), "expected a number, got \"" + token_ + "\"");
      }
      return value;
    }
    unsigned char bytes[8];
    const std::size_t size = sizeOf(type);
    if (!in_.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(size))) {
      fail(itemLocation(element, item), "file truncated");
    }
    const bool little = document_.format == Format::kBinaryLittleEndian;
    if (little != kHostLittleEndian) std::reverse(bytes, bytes + size);
    return decode(type, bytes);
  }

  void readElement(Element& element) {
    // No properties, no bytes: a huge count must not become a loop that reads nothing.
    if (element.properties.empty()) return;
    for (Property& property : element.properties) {
      if (property.isList()) {
        property.list_offsets.reserve(std::min(element.count, kMaxReservedItems) + 1);
        property.list_offsets.push_back(0);
        property.values.reserve(std::min(element.count, kMaxReservedItems) * 3);
      } else {
        property.values.reserve(std::min(element.count, kMaxReservedItems));
      }
    }
    for (std::size_t i = 0; i < element.count; ++i) {
      for (Property& property : element.properties) {
        if (!property.isList()) {
          property.values.push_back(readValue(property.type, element, i));
          continue;
        }
        const double count = readValue(*property.list_count_type, element, i);
        if (!(count >= 0) || count != std::floor(count)) {
          fail(itemLocation(element, i), "list \"" + property.name + "\" has an invalid count");
        }
        // A float count type can hold counts no std::size_t holds; no real list comes near this.
        if (count > static_cast<double>(kMaxListLength)) {
          fail(itemLocation(element, i), "list \"" + property.name + "\" has a count above " +
                                             std::to_string(kMaxListLength));
        }
        for (std::size_t k = 0; k < static_cast<std::size_t>(count); ++k) {
          property.values.push_back(readValue(property.type, element, i));
        }
        property.list_offsets.push_back(property.values.size());
      }
      if (check_) check_(element, i);
    }
  }

  std::istream& in_;
  std::string file_;
  const ItemCheck& check_;
  Document document_;
  std::string token_;  ///< ascii: the number being parsed (reused)
};

void checkCounts(const Document& document) {
  for (const Element& element : document.elements) {
    for (const Property& property : element.properties) {
      const std::string name = element.name + "." + property.name;
      if (property.isList()) {
        if (property.list_offsets.size() != element.count + 1 ||
            property.list_offsets.back() != property.values.size()) {
          throw std::invalid_argument("ply::write: list " + name + " needs count + 1 offsets ending at values.size()");
        }
      } else if (property.values.size() != element.count) {
        throw std::invalid_argument("ply::write: " + name + " has " + std::to_string(property.values.size()) +
                                    " values for " + std::to_string(element.count) + " items");
      }
    }
  }
}

void writeAsciiValue(std::ostream& out, Type type, double value) {
  if (isFloat(type)) {
    if (std::isnan(value)) out << "nan";
    else if (std::isinf(value)) out << (value > 0 ? "inf" : "-inf");
    else out << (type == Type::kFloat32 ? static_cast<double>(static_cast<float>(value)) : value);
  } else {
    out << static_cast<long long>(toIntegerValue(value, type));
  }
}

}  // namespace

std::size_t sizeOf(Type type) {
  switch (type) {
    case Type::kInt8:
    case Type::kUInt8: return 1;
    case Type::kInt16:
    case Type::kUInt16: return 2;
    case Type::kInt32:
    case Type::kUInt32:
    case Type::kFloat32: return 4;
    case Type::kFloat64: return 8;
  }
  return 0;
}

const char* nameOf(Type type) {
  switch (type) {
    case Type::kInt8: return "char";
    case Type::kUInt8: return "uchar";
    case Type::kInt16: return "short";
    case Type::kUInt16: return "ushort";
    case Type::kInt32: return "int";
    case Type::kUInt32: return "uint";
    case Type::kFloat32: return "float";
    case Type::kFloat64: return "double";
  }
  return "";
}

std::optional<Type> parseType(const std::string& name) {
  if (name == "char" || name == "int8") return Type::kInt8;
  if (name == "uchar" || name == "uint8") return Type::kUInt8;
  if (name == "short" || name == "int16") return Type::kInt16;
  if (name == "ushort" || name == "uint16") return Type::kUInt16;
  if (name == "int" || name == "int32") return Type::kInt32;
  if (name == "uint" || name == "uint32") return Type::kUInt32;
  if (name == "float" || name == "float32") return Type::kFloat32;
  if (name == "double" || name == "float64") return Type::kFloat64;
  return std::nullopt;
}

const Property* Element::find(const std::string& property_name) const {
  for (const Property& property : properties) {
    if (property.name == property_name) return &property;
  }
  return nullptr;
}

Property* Element::find(const std::string& property_name) {
  return const_cast<Property*>(static_cast<const Element&>(*this).find(property_name));
}

Property& Element::addScalar(const std::string& property_name, Type type) {
  Property property;
  property.name = property_name;
  property.type = type;
  properties.push_back(std::move(property));
  return properties.back();
}

Property& Element::addList(const std::string& property_name, Type count_type, Type item_type) {
  Property& property = addScalar(property_name, item_type);
  property.list_count_type = count_type;
  return property;
}

const Element* Document::find(const std::string& element_name) const {
  for (const Element& element : elements) {
    if (element.name == element_name) return &element;
  }
  return nullptr;
}

Element* Document::find(const std::string& element_name) {
  return const_cast<Element*>(static_cast<const Document&>(*this).find(element_name));
}

Element& Document::addElement(const std::string& element_name, std::size_t count) {
  Element element;
  element.name = element_name;
  element.count = count;
  elements.push_back(std::move(element));
  return elements.back();
}

Document read(std::istream& in, const std::string& file_name, const ItemCheck& check) {
  return Reader(in, file_name, check).read();
}

Document read(const std::filesystem::path& path, const ItemCheck& check) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading");
  return read(in, path.string(), check);
}

void write(std::ostream& out, const Document& document, Format format) {
  checkCounts(document);
  out << "ply\nformat "
      << (format == Format::kAscii                ? "ascii"
          : format == Format::kBinaryLittleEndian ? "binary_little_endian"
                                                  : "binary_big_endian")
      << " 1.0\n";
  for (const std::string& comment : document.comments) out << "comment " << comment << '\n';
  for (const Element& element : document.elements) {
    out << "element " << element.name << ' ' << element.count << '\n';
    for (const Property& property : element.properties) {
      out << "property ";
      if (property.isList()) out << "list " << nameOf(*property.list_count_type) << ' ';
      out << nameOf(property.type) << ' ' << property.name << '\n';
    }
  }
  out << "end_header\n";
  if (format == Format::kAscii) {
    out.precision(17);
    for (const Element& element : document.elements) {
      for (std::size_t i = 0; i < element.count; ++i) {
        const char* separator = "";
        for (const Property& property : element.properties) {
          out << separator;
          separator = " ";
          if (!property.isList()) {
            writeAsciiValue(out, property.type, property.values[i]);
            continue;
          }
          out << property.listSize(i);
          for (std::size_t k = property.list_offsets[i]; k < property.list_offsets[i + 1]; ++k) {
            out << ' ';
            writeAsciiValue(out, property.type, property.values[k]);
          }
        }
        out << '\n';
      }
    }
    return;
  }
  const bool swap = (format == Format::kBinaryLittleEndian) != kHostLittleEndian;
  std::vector<char> buffer;
  const auto put = [&](Type type, double value) {
    unsigned char bytes[8];
    encode(type, value, bytes);
    const std::size_t size = sizeOf(type);
    if (swap) std::reverse(bytes, bytes + size);
    buffer.insert(buffer.end(), bytes, bytes + size);
  };
  for (const Element& element : document.elements) {
    for (std::size_t i = 0; i < element.count; ++i) {
      for (const Property& property : element.properties) {
        if (!property.isList()) {
          put(property.type, property.values[i]);
          continue;
        }
        put(*property.list_count_type, static_cast<double>(property.listSize(i)));
        for (std::size_t k = property.list_offsets[i]; k < property.list_offsets[i + 1]; ++k) {
          put(property.type, property.values[k]);
        }
      }
      if (buffer.size() > (1u << 20)) {
        out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        buffer.clear();
      }
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

void writeFile(const std::filesystem::path& path, const Document& document, Format format) {
  checkCounts(document);
  writeFileAtomically(path, [&](std::ostream& out) { write(out, document, format); });
}

}  // namespace terramesh::ply
