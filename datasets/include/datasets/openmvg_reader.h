#pragma once

#include <filesystem>

#include "datasets/slam_stream.h"

namespace terramesh::datasets {

/// Reads an OpenMVG scene, `sfm_data.json` (any `sfm_data_version`), as a stream: one keyframe
/// event per view that has a pose, in increasing view key; keyframe id = view key, name = the
/// view's `filename`. `extrinsics[].value` gives `rotation` (3 rows, world to camera: OpenMVG's
/// x_C = R (x_W - C)) and `center` C; the keyframe takes C and R^T. Each `structure[]` entry is a
/// point (id = its key, position `X`) observed by the views its `observations[].key` name.
/// Views without a pose are skipped; intrinsics and 2D feature positions are ignored. Units are
/// the scene's (scale unknown).
/// @throw terramesh::InputError naming the file and the JSON path (or line and column for a
///        syntax error): a missing or mistyped field, a non-rotation, a non-finite number, a
///        duplicate view, pose or point key, an observation of an unknown or unposed view, or a
///        view listed twice in one point's observations.
SlamStream readOpenMvgSfmData(const std::filesystem::path& path);

}  // namespace terramesh::datasets
