#!/usr/bin/env bash
# Installs what is missing, builds in Release, then runs the main job on data the project makes
# itself: a synthetic street stream (with ground truth) is generated and meshed. Everything is
# written under out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
terramesh=build/apps/terramesh/terramesh
out=out/demo
mkdir -p "$out"
"$terramesh" generate street -o "$out/street" --length-m 300 --seed 1
"$terramesh" mesh "$out/street/stream.tmstream" -o "$out/mesh" --drop-steiner
echo
echo "demo: synthetic street and its ground truth in $out/street/, the mesh and the per-keyframe"
echo "table in $out/mesh/ (mesh.ply, mesh_open.ply, keyframes.csv, summary.txt)"
