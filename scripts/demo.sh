#!/usr/bin/env bash
# Installs what is missing, builds in Release, then runs the main job on data the project makes
# itself: a synthetic street stream (with ground truth) is generated and meshed, and the
# traversability map of the street is kept for a small wheeled robot. Everything is written under
# out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
# The CLI and, where npm is available, the viewer bundle: tests and benchmarks are not needed here.
targets=(--target terramesh)
if command -v npm >/dev/null 2>&1; then targets+=(--target terramesh_viewer); fi
scripts/build.sh "${targets[@]}"
terramesh=build/apps/terramesh/terramesh
out=out/demo
mkdir -p "$out"
"$terramesh" generate street -o "$out/street" --length-m 300 --seed 1
# The traversability map for a small wheeled robot is kept current after every keyframe and its
# exports (traversability.ply, Nav2 maps per level, GeoTIFF layers) are rewritten every 10.
"$terramesh" mesh "$out/street/stream.tmstream" -o "$out/mesh" --drop-steiner \
  --robot traversability/robots/small_wheeled.yaml --export-every 10 --snapshot-every 10
# The OctoMap baseline of the same camera-to-point rays, beside the mesh for the viewer's voxels.
"$terramesh" convert "$out/street/stream.tmstream" "$out/mesh/octomap.bt"
# A path for the robot on that map: five random start/goal pairs on its largest walkable component
# (OMPL's BIT*, with the face-graph optimum beside it), then a path between the first pair solved.
"$terramesh" plan "$out/mesh" --random-pairs 5 -o "$out/plan_pairs" --quiet
read -r sx sy sz gx gy gz < <(awk -F, '$8 == "solved" { print $2, $3, $4, $5, $6, $7; exit }' \
  "$out/plan_pairs/pairs.csv")
"$terramesh" plan "$out/mesh" --start "$sx" "$sy" "$sz" --goal "$gx" "$gy" "$gz" -o "$out/plan" --quiet
# The viewer shows the path found beside the map it serves.
cp "$out/plan/path.csv" "$out/mesh/path.csv"
# Figures (matplotlib): a top view coloured by cost with the trajectory and the path, histograms.
python3=/usr/bin/python3
[ -x "$python3" ] || python3=python3
"$python3" scripts/figures/traversability_figures.py "$out/mesh" --path "$out/plan/path.csv" \
  --trajectory "$out/street/trajectory.txt" -o "$out/figures"
"$python3" scripts/figures/planner_figures.py "$out/plan_pairs/pairs.csv" -o "$out/figures"
echo
echo "demo: synthetic street and its ground truth in $out/street/, the mesh and the per-keyframe"
echo "table in $out/mesh/ (mesh.ply, mesh_open.ply, keyframes.csv, summary.txt, snapshots/,"
echo "octomap.bt: the OctoMap baseline of the same rays), and the"
echo "traversability map beside it: traversability.ply (per-face layers: MeshLab, CloudCompare),"
echo "level_N.yaml + level_N.pgm (Nav2 map_server, trinary), level_N_cost.yaml + .png (scale mode),"
echo "layers_level_N.tif (GeoTIFF, one band per layer), traversability_summary.txt and"
echo "traversability_updates.csv (per-keyframe layer update times); a planned path in $out/plan/"
echo "(path.csv, path.ply, plan.txt); figures in $out/figures/."
echo "To look at it in a browser: $terramesh view $out/mesh   (serves on 127.0.0.1, prints the URL)"
