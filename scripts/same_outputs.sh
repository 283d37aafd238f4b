#!/usr/bin/env bash
# Whether a change left every output as it was: builds the CLI at BASE (a commit; default the
# commit before HEAD) in a temporary worktree, runs the same commands with it and with this
# checkout's build, and compares every file they write (scripts/same_outputs_cmp.py: byte for
# byte, except the times, memory figures and the planner's time-limited searches that no two runs
# share). The commands: the demo's pipeline (street, small_wheeled, exports every 10 keyframes,
# OctoMap conversion, random pairs and one path with the face-graph planner), street, offroad and
# garage in the three mesher modes with a robot, KITTI 00 (ORB-SLAM) with every shipped robot,
# `traverse` and `plan --robot` on a finished map, and `compare` on the street.
# Usage: scripts/same_outputs.sh [BASE] (env: TERRAMESH_BUILD, the build to test, default build/;
# TERRAMESH_SAME_OUT, default out/same_outputs). Exit 0 when all are identical, 1 if any differ.
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:-HEAD~1}
head_build=${TERRAMESH_BUILD:-build}
shared=${TERRAMESH_SHARED_DIR:-../shared}
out=${TERRAMESH_SAME_OUT:-out/same_outputs}
base_sha=$(git rev-parse --verify "$base^{commit}")
rm -rf "$out"
mkdir -p "$out"
work=$(mktemp -d)
trap 'git worktree remove --force "$work/src" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
git worktree add --detach "$work/src" "$base_sha" >/dev/null
echo "building $base_sha in $work/src (terramesh only)"
launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$work/src"  # as build.sh: paths relative to the checkout share the cache
fi
(cd "$work/src" && cmake -S . -B "$work/build" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" \
  -DTERRAMESH_SHARED_DIR="$(realpath "$shared")" && cmake --build "$work/build" -j2 --target terramesh) \
  >"$out/base_build.log" 2>&1 || { echo "same_outputs: building $base_sha failed (see $out/base_build.log)" >&2; exit 2; }
unset CCACHE_BASEDIR

# run BINARY DIR: every command, outputs under DIR.
run() {
  local t=$1 d=$2
  mkdir -p "$d"
  "$t" generate street -o "$d/street" --length-m 300 --seed 1 --quiet
  "$t" mesh "$d/street/stream.tmstream" -o "$d/demo" --drop-steiner --robot traversability/robots/small_wheeled.yaml \
    --export-every 10 --snapshot-every 10 --quiet
  "$t" convert "$d/street/stream.tmstream" "$d/demo/octomap.bt" >/dev/null
  "$t" plan "$d/demo" --planner graph --random-pairs 5 -o "$d/demo_pairs" --quiet
  # A pair the graph joined (graph_cost finite), whatever the pairs' own planner found.
  read -r sx sy sz gx gy gz < <(awk -F, 'NR > 1 && $12 != "nan" && $12 != "inf" { print $2, $3, $4, $5, $6, $7; exit }' \
    "$d/demo_pairs/pairs.csv")
  "$t" plan "$d/demo" --planner graph --start "$sx" "$sy" "$sz" --goal "$gx" "$gy" "$gz" -o "$d/demo_plan" --quiet
  "$t" plan "$d/demo" --planner graph --robot traversability/robots/legged.yaml --random-pairs 3 -o "$d/demo_pairs_legged" --quiet
  "$t" traverse "$d/demo/mesh.ply" --robot traversability/robots/car.yaml -o "$d/demo_car" --quiet
  for scene in street offroad garage; do
    [[ $scene == street ]] || "$t" generate "$scene" -o "$d/$scene" --seed 1 --quiet
    for mode in proposed litvinov13 romanoni15; do
      "$t" mesh "$d/$scene/stream.tmstream" --mode "$mode" --robot traversability/robots/legged.yaml \
        -o "$d/${scene}_$mode" --quiet
    done
  done
  local stream=$shared/data/kitti00_orbslam/slam_data_version0.1_KITTI00_50frames.json
  for robot in traversability/robots/*.yaml; do
    "$t" mesh "$stream" --robot "$robot" --metres-per-unit 16.589 -o "$d/kitti00_$(basename "$robot" .yaml)" --quiet
  done
  "$t" compare "$d/street/stream.tmstream" --gt "$d/street/ground_truth.ply" --robot traversability/robots/small_wheeled.yaml \
    --methods proposed,octomap-0.2,greedy --pairs 3 -o "$d/compare" >/dev/null
}

echo "running the base ($base_sha)"
run "$work/build/apps/terramesh/terramesh" "$out/base"
echo "running this build ($head_build)"
run "$head_build/apps/terramesh/terramesh" "$out/head"
python3=/usr/bin/python3
[ -x "$python3" ] || python3=python3
"$python3" scripts/same_outputs_cmp.py "$out/base" "$out/head"
