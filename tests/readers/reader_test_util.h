#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

#include "common/input_error.h"
#include "datasets/slam_stream.h"

namespace terramesh::test {

/// A file or folder of the shared real data (../shared/data).
std::filesystem::path sharedData(const std::string& relative);

/// Counts that describe a stream.
struct StreamCounts {
  std::size_t keyframe_events = 0;
  std::size_t distinct_keyframes = 0;
  std::size_t distinct_points = 0;
  std::size_t observations = 0;

  friend bool operator==(const StreamCounts& a, const StreamCounts& b) {
    return a.keyframe_events == b.keyframe_events && a.distinct_keyframes == b.distinct_keyframes &&
           a.distinct_points == b.distinct_points && a.observations == b.observations;
  }
  friend std::ostream& operator<<(std::ostream& out, const StreamCounts& c) {
    return out << "{" << c.keyframe_events << " keyframe events, " << c.distinct_keyframes
               << " keyframe ids, " << c.distinct_points << " points, " << c.observations
               << " observations}";
  }
};
StreamCounts countStream(const datasets::SlamStream& stream);

/// The keyframe events of a stream, in order.
std::vector<mesher::Keyframe> keyframesOf(const datasets::SlamStream& stream);

/// Whether two streams have the same events (ids, centres, rotations as matrices, observation
/// ids and positions, in order) and keyframe names, within `tolerance` (0: bit for bit).
::testing::AssertionResult sameStreams(const datasets::SlamStream& a, const datasets::SlamStream& b,
                                       double tolerance = 0.0);

/// Runs `read`, which must throw terramesh::InputError, and returns the error. A failure is
/// recorded if it throws something else or nothing.
InputError expectInputError(const std::function<void()>& read);

/// Checks an error's file, and that its location and problem contain the given texts.
void expectErrorAt(const InputError& error, const std::filesystem::path& file,
                   const std::string& where_part, const std::string& problem_part);

std::string readFile(const std::filesystem::path& path);
void writeFile(const std::filesystem::path& path, const std::string& content);
/// Overwrites bytes of a file in place, at `offset`.
void patchFile(const std::filesystem::path& path, std::size_t offset, const void* bytes,
               std::size_t size);
/// Copies every file of `from` (not recursive) into `to`, which is created, as writable files.
void copyFiles(const std::filesystem::path& from, const std::filesystem::path& to);

/// Replaces the `line_number`-th line (1-based) of a text file.
void replaceLine(const std::filesystem::path& path, std::size_t line_number,
                 const std::string& line);

}  // namespace terramesh::test
