#!/usr/bin/env bash
# Installs what is missing, builds in Release, then runs the main job on data the project makes
# itself: a synthetic street stream (with ground truth) is generated and meshed, and the
# traversability map of the street is kept for a small wheeled robot. Everything is written under
# out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh --target terramesh  # the CLI alone: tests and benchmarks are not needed here
terramesh=build/apps/terramesh/terramesh
out=out/demo
mkdir -p "$out"
"$terramesh" generate street -o "$out/street" --length-m 300 --seed 1
# The traversability map for a small wheeled robot is kept current after every keyframe and its
# exports (traversability.ply, Nav2 maps per level, GeoTIFF layers) are rewritten every 10.
"$terramesh" mesh "$out/street/stream.tmstream" -o "$out/mesh" --drop-steiner \
  --robot traversability/robots/small_wheeled.yaml --export-every 10
echo
echo "demo: synthetic street and its ground truth in $out/street/, the mesh and the per-keyframe"
echo "table in $out/mesh/ (mesh.ply, mesh_open.ply, keyframes.csv, summary.txt), and the"
echo "traversability map beside it: traversability.ply (per-face layers: MeshLab, CloudCompare),"
echo "level_N.yaml + level_N.pgm (Nav2 map_server, trinary), level_N_cost.yaml + .png (scale mode),"
echo "layers_level_N.tif (GeoTIFF, one band per layer), traversability_summary.txt and"
echo "traversability_updates.csv (per-keyframe layer update times)"
