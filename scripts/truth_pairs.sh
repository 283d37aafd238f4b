#!/usr/bin/env bash
# Start/goal pairs the truth decides, planned on a map: for each pair of `terramesh pairs` (random
# walkable pairs and the hazards scene's crossings), runs `terramesh plan` and compares its outcome
# with the truth's reachability. A pair the truth calls unreachable must exit 3; a pair it calls
# reachable should connect (exit 0). Prints one markdown row per pair and a count per outcome.
#
#   scripts/truth_pairs.sh SCENE_DIR MAP_DIR ROBOT.yaml [PLANNER]
#
# SCENE_DIR holds ground_truth.ply (and trajectory.txt, hazards.csv) of `terramesh generate`;
# MAP_DIR is a map of that scene's stream (`terramesh mesh STREAM --robot ROBOT.yaml -o MAP_DIR`).
# PLANNER defaults to graph (A* on the face graph: deterministic). Expects a Release build in
# build/ (or TERRAMESH_BUILD=dir). Whether a connecting path is also drivable on the truth is
# planner_demo's strict check, not this script's. TERRAMESH_PLAN_ARGS adds arguments to every
# `terramesh plan` (e.g. --allow-uncertain).
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ $# -lt 3 ]]; then
  echo "usage: scripts/truth_pairs.sh SCENE_DIR MAP_DIR ROBOT.yaml [PLANNER]" >&2
  exit 2
fi
scene=$1 map=$2 robot=$3 planner=${4:-graph}
terramesh=${TERRAMESH_BUILD:-build}/apps/terramesh/terramesh
plan_args=(${TERRAMESH_PLAN_ARGS:-})
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$terramesh" pairs "$scene/ground_truth.ply" --robot "$robot" -o "$work/pairs.csv" --quiet

echo "| pair | truth | plan exit | outcome | plan says |"
echo "|---|---|---|---|---|"
declare -A count=()
while IFS=$'\t' read -r name sx sy sz gx gy gz reachable reason; do
  set +e
  "$terramesh" plan "$map" --robot "$robot" --planner "$planner" --start "$sx" "$sy" "$sz" --goal "$gx" "$gy" "$gz" \
 \
    "${plan_args[@]}" -o "$work/plan_$name" --quiet > "$work/out.txt" 2> "$work/err.txt"
  code=$?
  set -e
  if [[ $reachable == 1 && $code == 0 ]]; then outcome="connected"
  elif [[ $reachable == 1 && $code == 3 ]]; then outcome="missed"
  elif [[ $reachable == 0 && $code == 3 ]]; then outcome="refused"
  elif [[ $reachable == 0 && $code == 0 ]]; then outcome="PATH WHERE THE TRUTH HAS NONE"
  else outcome="error $code"
  fi
  count[$outcome]=$((${count[$outcome]:-0} + 1))
  says=$(head -c 160 "$work/err.txt" | tr '\n|' '  ')
  echo "| $name | $([[ $reachable == 1 ]] && echo reachable || echo "unreachable ($reason)") | $code | $outcome | $says |"
done < <(awk -F, 'NR > 1 { printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", $3, $4, $5, $6, $7, $8, $9, $10, $11 }' \
  "$work/pairs.csv")
echo
for outcome in "${!count[@]}"; do echo "- $outcome: ${count[$outcome]}"; done | sort
