#pragma once

#include <filesystem>

#include "datasets/colmap_reader.h"

namespace terramesh::test {

/// Writes cameras.txt, images.txt and points3D.txt as COLMAP does, with round-trip precision.
void writeColmapText(const std::filesystem::path& directory, const datasets::ColmapModel& model);

/// Writes cameras.bin, images.bin and points3D.bin as COLMAP does (little-endian).
void writeColmapBinary(const std::filesystem::path& directory, const datasets::ColmapModel& model);

/// Converts a COLMAP model to Bundler v0.3 (`bundle_path`) and its image list (`list_path`):
/// camera i is the i-th image in increasing image id, point j the j-th 3D point in file order,
/// with view lists from the points' tracks. R and t are flipped into Bundler's y-up, -z-forward
/// camera; f is the camera's first parameter. Round-trip precision.
void writeBundlerFromColmap(const std::filesystem::path& bundle_path,
                            const std::filesystem::path& list_path,
                            const datasets::ColmapModel& model);

/// Writes the model as OpenSfM's `export_bundler` names its files: `bundle_r000.out` and
/// `list_r000.out` in `directory` (image names as `images/NAME 0 FOCAL`), as
/// writeBundlerFromColmap. Returns the path of the bundle file.
std::filesystem::path writeOpenSfmBundlerExport(const std::filesystem::path& directory,
                                                const datasets::ColmapModel& model);

}  // namespace terramesh::test
