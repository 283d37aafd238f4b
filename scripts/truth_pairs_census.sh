#!/usr/bin/env bash
# The truth's start/goal pairs on every scene, seed and shipped robot: generates each scene
# (`terramesh generate SCENE --seed S`), meshes it with the robot's layers (`terramesh mesh --robot`,
# the profile without its sensor mounting: the generator's rig is not KITTI's), runs
# scripts/truth_pairs.sh on the map and prints one markdown row per scene and seed, each cell a
# robot's counts: connected and valid / invalid on the truth / path where the truth has none /
# missed with an end off known ground / missed / refused (the truth has no path).
#   scripts/truth_pairs_census.sh [OUT_DIR]     (default out/truth_pairs_census)
# Env: TERRAMESH_CENSUS_SCENES (default "hazards street offroad garage"), TERRAMESH_CENSUS_SEEDS
# (default "1 2 3 4 5" for hazards, 1 for the others), TERRAMESH_BUILD (default build/). Each
# robot's per-pair table is kept in OUT_DIR/SCENE_sS_ROBOT.pairs.txt. About 10 min on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
terramesh=${TERRAMESH_BUILD:-build}/apps/terramesh/terramesh
out=${1:-out/truth_pairs_census}
mkdir -p "$out/profiles"
robots=()
for robot_file in traversability/robots/*.yaml; do
  robot=$(basename "$robot_file" .yaml)
  grep -v -E '^(sensor_height_m|sensor_pose_in_base)' "$robot_file" > "$out/profiles/$robot.yaml"
  robots+=("$robot")
done

# The counts of one truth_pairs.sh table, in the column order above.
counts() {
  awk -F': ' '/^- / { n[substr($1, 3)] = $2 } END {
      printf "%d / %d / %d / %d / %d / %d", n["connected"], n["CONNECTED, INVALID ON THE TRUTH"],
        n["PATH WHERE THE TRUTH HAS NONE"], n["missed (end off known ground)"], n["missed"], n["refused"]
    }' "$1"
}

header="| scene | seed |"
rule="|---|---|"
for robot in "${robots[@]}"; do
  header+=" $robot |"
  rule+="---|"
done
echo "cells: connected and valid / invalid on the truth / path where the truth has none / missed (end off known ground) / missed / refused"
echo
echo "$header"
echo "$rule"
for scene in ${TERRAMESH_CENSUS_SCENES:-hazards street offroad garage}; do
  default_seeds=1
  [[ $scene == hazards ]] && default_seeds="1 2 3 4 5"
  for seed in ${TERRAMESH_CENSUS_SEEDS:-$default_seeds}; do
    scene_dir="$out/${scene}_s$seed"
    "$terramesh" generate "$scene" -o "$scene_dir" --seed "$seed" --quiet
    line="| $scene | $seed |"
    for robot in "${robots[@]}"; do
      map="$out/${scene}_s${seed}_$robot"
      "$terramesh" mesh "$scene_dir/stream.tmstream" --robot "$out/profiles/$robot.yaml" -o "$map" --quiet
      scripts/truth_pairs.sh "$scene_dir" "$map" "$out/profiles/$robot.yaml" > "$map.pairs.txt"
      line+=" $(counts "$map.pairs.txt") |"
    done
    echo "$line"
  done
done
