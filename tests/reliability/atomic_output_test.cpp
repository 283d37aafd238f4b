// Every output is written through a temporary file renamed into place (common/atomic_file.h): a
// writer that fails midway, or cannot write at all, leaves the previous file exactly as it was and
// no temporary file behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "common/atomic_file.h"
#include "mesher/checkpoint.h"
#include "mesher/mesh_io.h"
#include "mesher/mesher.h"

namespace terramesh {
namespace {

namespace fs = std::filesystem;

/// A fresh directory, removed (permissions restored) at the end.
class ScratchDir {
 public:
  ScratchDir() {
    path_ = fs::temp_directory_path() / ("terramesh_atomic_" + std::to_string(::getpid()) + "_" +
                                         std::to_string(counter_++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ignored);
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  fs::path path_;
};

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(AtomicOutput, AWriterFailingMidwayLeavesThePreviousFileIntact) {
  ScratchDir dir;
  const fs::path path = dir.path() / "keyframes.csv";
  writeFileAtomically(path, std::string("previous,complete\n1,2\n"));
  EXPECT_THROW(writeFileAtomically(path,
                                   [](std::ostream& out) {
                                     out << "new,partial\n";
                                     for (int i = 0; i < 100000; ++i) out << i << ",x\n";
                                     throw std::runtime_error("disk full (injected)");
                                   }),
               std::runtime_error);
  EXPECT_EQ(readAll(path), "previous,complete\n1,2\n");
  EXPECT_EQ(entries(dir.path()), 1u) << "no temporary file may be left behind";
}

TEST(AtomicOutput, AFailedCheckpointWriteLeavesThePreviousCheckpointLoadable) {
  ScratchDir dir;
  const fs::path path = dir.path() / "checkpoint.tmckpt";
  mesher::Mesher mesher(mesher::MesherConfig{});
  writeFileAtomically(path, [&](std::ostream& out) { mesher::saveCheckpoint(mesher, out, "first"); });
  const std::string first = readAll(path);
  // The new checkpoint's bytes go out, then the write fails before the rename.
  EXPECT_THROW(writeFileAtomically(path,
                                   [&](std::ostream& out) {
                                     mesher::saveCheckpoint(mesher, out, "second");
                                     throw std::runtime_error("killed before the rename (injected)");
                                   }),
               std::runtime_error);
  EXPECT_EQ(readAll(path), first);
  std::ifstream in(path, std::ios::binary);
  EXPECT_EQ(mesher::loadCheckpoint(in, path.string()).app_data, "first");
  EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(AtomicOutput, AnUnwritableDirectoryFailsCleanlyAndKeepsTheOldMesh) {
  if (::geteuid() == 0) GTEST_SKIP() << "root ignores directory permissions";
  ScratchDir dir;
  const fs::path path = dir.path() / "mesh.ply";
  mesher::TriangleMesh tetrahedron;
  tetrahedron.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetrahedron.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  mesher::writePly(path, tetrahedron);
  const std::string before = readAll(path);
  fs::permissions(dir.path(), fs::perms::owner_read | fs::perms::owner_exec, fs::perm_options::replace);
  tetrahedron.vertices[3] = {0, 0, 2};
  try {
    mesher::writePly(path, tetrahedron);
    ADD_FAILURE() << "writing into a read-only directory succeeded";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
  }
  fs::permissions(dir.path(), fs::perms::owner_all, fs::perm_options::replace);
  EXPECT_EQ(readAll(path), before);
  EXPECT_EQ(entries(dir.path()), 1u);
}

}  // namespace
}  // namespace terramesh
