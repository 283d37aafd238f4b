// json::readJsonFile, writeJsonFile and FieldReader, the one home of checked JSON: every error
// names the file, where (the line and column, or the JSON path) and what was expected.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/input_error.h"
#include "common/json_fields.h"

namespace terramesh::json {
namespace {

namespace fs = std::filesystem;

class JsonFieldsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("terramesh_json_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }

  /// The InputError `f()` throws (a failure if none).
  template <class F>
  static InputError errorOf(F&& f) {
    try {
      f();
    } catch (const InputError& error) {
      return error;
    }
    ADD_FAILURE() << "expected an InputError";
    return InputError("", "", "");
  }

  fs::path dir_;
};

TEST_F(JsonFieldsTest, AWrittenFileReadsBackWithMode0644) {
  const nlohmann::json value = {{"format", "x"}, {"version", 2}, {"list", {1, 2, 3}}};
  writeJsonFile(dir_ / "a.json", value);
  EXPECT_EQ(readJsonFile(dir_ / "a.json", "a test file"), value);
  struct stat info {};
  ASSERT_EQ(::stat((dir_ / "a.json").c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0644u);
}

TEST_F(JsonFieldsTest, MalformedOrMissingFilesNameTheLineAndWhatWasExpected) {
  const fs::path bad = write("bad.json", "{\n  \"a\": 1,\n  \"b\": ]\n}\n");
  const InputError error = errorOf([&] { readJsonFile(bad, "a tile plan"); });
  EXPECT_EQ(error.file(), bad.string());
  EXPECT_EQ(error.where(), "line 3, column 8");
  EXPECT_NE(std::string(error.what()).find("malformed JSON (expected a tile plan)"), std::string::npos) << error.what();
  const InputError missing = errorOf([&] { readJsonFile(dir_ / "absent.json", "a tile plan"); });
  EXPECT_NE(std::string(missing.what()).find("cannot open"), std::string::npos) << missing.what();
  const InputError huge = errorOf([&] { readJsonFile(write("huge.json", "[1e999]"), "numbers"); });
  EXPECT_NE(std::string(huge.what()).find("number out of range"), std::string::npos) << huge.what();
}

TEST_F(JsonFieldsTest, FieldsAreReadByTheirPathAndCheckedForTheirType) {
  const nlohmann::json root = nlohmann::json::parse(
      R"({"format": "f", "version": 1, "tiles": [{"n": 3, "x": 1.5, "name": "t", "neg": -2}], "obj": 4})");
  const FieldReader reader("plan.json");
  EXPECT_NO_THROW(reader.header(root, "f", 1));
  const nlohmann::json& tiles = reader.array(root, "tiles", "");
  const std::string tile = FieldReader::at("tiles", 0);
  EXPECT_EQ(tile, "tiles[0]");
  EXPECT_EQ(reader.count(tiles[0], "n", tile), 3u);
  EXPECT_DOUBLE_EQ(reader.number(tiles[0], "x", tile), 1.5);
  EXPECT_EQ(reader.string(tiles[0], "name", tile), "t");
  EXPECT_EQ(reader.integer(tiles[0], "neg", tile), -2);
  const auto where = [&](auto&& f) {
    const InputError error = errorOf(f);
    EXPECT_EQ(error.file(), "plan.json");
    return error.where() + ": " + error.what();
  };
  EXPECT_NE(where([&] { reader.number(tiles[0], "y", tile); }).find("tiles[0].y"), std::string::npos);
  EXPECT_NE(where([&] { reader.number(tiles[0], "name", tile); }).find("expected a number"), std::string::npos);
  EXPECT_NE(where([&] { reader.count(tiles[0], "neg", tile); }).find("expected an integer >= 0"), std::string::npos);
  EXPECT_NE(where([&] { reader.integer(tiles[0], "x", tile); }).find("expected an integer"), std::string::npos);
  EXPECT_NE(where([&] { reader.member(reader.member(root, "obj", ""), "k", "obj"); }).find("obj: "), std::string::npos);
  EXPECT_NE(where([&] { reader.array(root, "obj", ""); }).find("expected an array"), std::string::npos);
  EXPECT_NE(where([&] { reader.header(root, "g", 1); }).find("format"), std::string::npos);
  EXPECT_NE(where([&] { reader.header(root, "f", 2); }).find("version"), std::string::npos);
}

}  // namespace
}  // namespace terramesh::json
