// The generic PLY module (common/ply.h): round trips in every encoding, hand-made ascii and
// big-endian files, value conversion and errors naming the file and place.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "common/input_error.h"
#include "common/ply.h"
#include "test_support/temp_dir.h"

namespace terramesh::ply {
namespace {

Document sampleDocument() {
  Document document;
  document.comments.push_back("sample");
  Element& vertex = document.addElement("vertex", 3);
  vertex.addScalar("x", Type::kFloat64).values = {0.1, -2.5e10, 1.0 / 3.0};
  vertex.addScalar("cost", Type::kFloat32).values = {0.25, std::numeric_limits<double>::quiet_NaN(),
                                                      std::numeric_limits<double>::infinity()};
  vertex.addScalar("flag", Type::kUInt8).values = {0, 1, 255};
  vertex.addScalar("offset", Type::kInt16).values = {-32768, 7, 32767};
  vertex.addScalar("count", Type::kUInt32).values = {0, 4294967295.0, 12};
  Element& face = document.addElement("face", 2);
  Property& indices = face.addList("vertex_indices", Type::kUInt8, Type::kInt32);
  indices.values = {0, 1, 2, 2, 1, 0, -1};
  indices.list_offsets = {0, 3, 7};
  face.addScalar("tag", Type::kInt8).values = {-5, 5};
  return document;
}

bool sameValue(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

void expectEqual(const Document& a, const Document& b) {
  ASSERT_EQ(a.elements.size(), b.elements.size());
  EXPECT_EQ(a.comments, b.comments);
  for (std::size_t e = 0; e < a.elements.size(); ++e) {
    const Element &x = a.elements[e], &y = b.elements[e];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.count, y.count);
    ASSERT_EQ(x.properties.size(), y.properties.size());
    for (std::size_t p = 0; p < x.properties.size(); ++p) {
      const Property &u = x.properties[p], &v = y.properties[p];
      EXPECT_EQ(u.name, v.name);
      EXPECT_EQ(u.type, v.type);
      EXPECT_EQ(u.list_count_type, v.list_count_type);
      EXPECT_EQ(u.list_offsets, v.list_offsets);
      ASSERT_EQ(u.values.size(), v.values.size()) << u.name;
      for (std::size_t i = 0; i < u.values.size(); ++i) {
        const double expected = u.type == Type::kFloat32 ? static_cast<double>(static_cast<float>(u.values[i])) : u.values[i];
        EXPECT_TRUE(sameValue(expected, v.values[i])) << u.name << "[" << i << "]: " << expected << " vs " << v.values[i];
      }
    }
  }
}

class PlyRoundTrip : public ::testing::TestWithParam<Format> {};

TEST_P(PlyRoundTrip, WriteThenReadGivesTheSameDocument) {
  const Document document = sampleDocument();
  std::stringstream buffer;
  write(buffer, document, GetParam());
  const Document read_back = read(buffer, "memory.ply");
  EXPECT_EQ(read_back.format, GetParam());
  expectEqual(document, read_back);
}

INSTANTIATE_TEST_SUITE_P(AllFormats, PlyRoundTrip,
                         ::testing::Values(Format::kAscii, Format::kBinaryLittleEndian, Format::kBinaryBigEndian));

TEST(Ply, ReadsHandWrittenAscii) {
  std::istringstream in(
      "ply\r\nformat ascii 1.0\ncomment made by hand\nobj_info x\nelement vertex 2\nproperty float32 x\n"
      "property uint8 k\nelement face 1\nproperty list uchar uint vertex_index\nend_header\n"
      "1.5 3\n-2e-3 4\n3 0 1 1\n");
  const Document document = read(in, "hand.ply");
  EXPECT_EQ(document.format, Format::kAscii);
  ASSERT_EQ(document.comments.size(), 1u);
  EXPECT_EQ(document.comments[0], "made by hand");
  const Element* vertex = document.find("vertex");
  ASSERT_NE(vertex, nullptr);
  EXPECT_EQ(vertex->find("x")->values, (std::vector<double>{1.5, -2e-3}));
  EXPECT_EQ(vertex->find("k")->type, Type::kUInt8);
  const Property* list = document.find("face")->find("vertex_index");
  ASSERT_NE(list, nullptr);
  EXPECT_EQ(list->values, (std::vector<double>{0, 1, 1}));
  EXPECT_EQ(list->listSize(0), 3u);
}

TEST(Ply, ReadsHandMadeBigEndianBytes) {
  std::string bytes = "ply\nformat binary_big_endian 1.0\nelement v 1\nproperty int a\nproperty float b\n"
                      "property ushort c\nend_header\n";
  bytes += std::string("\x00\x00\x01\x02", 4);  // 258
  bytes += std::string("\x3F\xC0\x00\x00", 4);  // 1.5f
  bytes += std::string("\xFF\xFE", 2);          // 65534
  std::istringstream in(bytes);
  const Document document = read(in, "be.ply");
  const Element& v = document.elements.at(0);
  EXPECT_EQ(v.find("a")->values[0], 258);
  EXPECT_EQ(v.find("b")->values[0], 1.5);
  EXPECT_EQ(v.find("c")->values[0], 65534);
}

TEST(Ply, LittleEndianBytesAreLaidOutAsTheSpecSays) {
  Document document;
  document.addElement("v", 1).addScalar("a", Type::kUInt32).values = {0x01020304};
  std::ostringstream out;
  write(out, document, Format::kBinaryLittleEndian);
  const std::string text = out.str();
  EXPECT_EQ(text.substr(text.size() - 4), std::string("\x04\x03\x02\x01", 4));
  std::ostringstream big;
  write(big, document, Format::kBinaryBigEndian);
  EXPECT_EQ(big.str().substr(big.str().size() - 4), std::string("\x01\x02\x03\x04", 4));
}

TEST(Ply, IntegersAreRoundedAndClamped) {
  Document document;
  document.addElement("v", 4).addScalar("a", Type::kUInt8).values = {300, -4, 2.6, std::nan("")};
  std::stringstream buffer;
  write(buffer, document, Format::kBinaryLittleEndian);
  EXPECT_EQ(read(buffer, "m").elements[0].properties[0].values, (std::vector<double>{255, 0, 3, 0}));
}

TEST(Ply, MismatchedCountsAreRefusedOnWrite) {
  Document document;
  document.addElement("v", 2).addScalar("a", Type::kFloat32).values = {1};
  std::ostringstream out;
  EXPECT_THROW(write(out, document, Format::kAscii), std::invalid_argument);
  Document lists;
  lists.addElement("f", 1).addList("i", Type::kUInt8, Type::kInt32).values = {1, 2};
  EXPECT_THROW(write(out, lists, Format::kAscii), std::invalid_argument);
}

std::string errorOf(const std::string& text) {
  std::istringstream in(text);
  try {
    read(in, "bad.ply");
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), "bad.ply");
    return error.what();
  }
  ADD_FAILURE() << "no error for: " << text;
  return "";
}

TEST(Ply, ErrorsNameTheHeaderLineOrTheElementItem) {
  EXPECT_NE(errorOf("PLY\n").find("line 1"), std::string::npos);
  EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement v 1\nproperty quad a\nend_header\n").find("line 4"),
            std::string::npos);
  EXPECT_NE(errorOf("ply\nformat utf8 1.0\nend_header\n").find("line 2"), std::string::npos);
  EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement v 1\n").find("end_header"), std::string::npos);
  EXPECT_NE(errorOf("ply\nelement v 0\nend_header\n").find("format"), std::string::npos);
  EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement face 2\nproperty float a\nend_header\n1\nx\n").find("face 1"),
            std::string::npos);
  std::string truncated = "ply\nformat binary_little_endian 1.0\nelement face 2\nproperty int a\nend_header\n";
  truncated += std::string(6, '\0');
  EXPECT_NE(errorOf(truncated).find("face 1"), std::string::npos);
  EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement f 1\nproperty list uchar int i\nend_header\n-1\n").find("f 0"),
            std::string::npos);
}

TEST(Ply, FilesAreWrittenAtomicallyAndReadBack) {
  test::TempDir dir;
  const Document document = sampleDocument();
  writeFile(dir / "a.ply", document, Format::kBinaryBigEndian);
  expectEqual(document, read(dir / "a.ply"));
  EXPECT_THROW(read(dir / "missing.ply"), InputError);
}

}  // namespace
}  // namespace terramesh::ply
