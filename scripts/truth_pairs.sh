#!/usr/bin/env bash
# Start/goal pairs the truth decides, planned on a map: for each pair of `terramesh pairs` (random
# walkable pairs and the hazards scene's crossings), runs `terramesh plan` and compares its outcome
# with the truth's reachability. A pair the truth calls unreachable must exit 3; a pair it calls
# reachable should connect (exit 0). Prints one markdown row per pair and a count per outcome.
#
#   scripts/truth_pairs.sh SCENE_DIR MAP_DIR ROBOT.yaml [PLANNER]
#
# SCENE_DIR holds ground_truth.ply (and trajectory.txt, hazards.csv) of `terramesh generate`;
# MAP_DIR is a map of that scene's stream (`terramesh mesh STREAM --robot ROBOT.yaml -o MAP_DIR`);
# the pairs are drawn on the truth for ROBOT.yaml, and planned on the map's own layers (the online
# map's, unconfirmed points included, which a recomputation from mesh.ply would not see).
# PLANNER defaults to graph (A* on the face graph: deterministic). Expects a Release build in
# build/ (or TERRAMESH_BUILD=dir). A miss is "missed (end off known ground)" when the map has no
# known walkable face at the start or the goal, else "missed". Every connecting path is then checked
# on the truth with planner_demo's strict check (`terramesh traverse-eval --path`): "connected" if
# it passes, "CONNECTED, INVALID ON THE TRUTH" and the first failure if not. TERRAMESH_PLAN_ARGS adds
# arguments to every `terramesh plan` (e.g. --allow-uncertain).
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

declare -A count=() outcome_of=() truth_of=() code_of=() says_of=()
names=() paths=()
while IFS=$'\t' read -r name sx sy sz gx gy gz reachable reason; do
  set +e
  "$terramesh" plan "$map" --planner "$planner" --start "$sx" "$sy" "$sz" --goal "$gx" "$gy" "$gz" \
 \
    "${plan_args[@]}" -o "$work/plan_$name" --quiet > "$work/out.txt" 2> "$work/err.txt"
  code=$?
  set -e
  if [[ $reachable == 1 && $code == 0 ]]; then outcome="connected"
  elif [[ $reachable == 1 && $code == 3 ]] && grep -q "no known walkable face" "$work/err.txt"; then
    outcome="missed (end off known ground)"
  elif [[ $reachable == 1 && $code == 3 ]]; then outcome="missed"
  elif [[ $reachable == 0 && $code == 3 ]]; then outcome="refused"
  elif [[ $reachable == 0 && $code == 0 ]]; then outcome="PATH WHERE THE TRUTH HAS NONE"
  else outcome="error $code"
  fi
  names+=("$name")
  outcome_of[$name]=$outcome
  truth_of[$name]=$([[ $reachable == 1 ]] && echo reachable || echo "unreachable ($reason)")
  code_of[$name]=$code
  says_of[$name]=$(head -c 160 "$work/err.txt" | tr '\n|' '  ')
  if [[ $code == 0 ]]; then paths+=("$work/plan_$name/path.csv"); fi
done < <(awk -F, 'NR > 1 { printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", $3, $4, $5, $6, $7, $8, $9, $10, $11 }' \
  "$work/pairs.csv")

# Every path planned, on the truth (one traverse-eval for all of them).
if [[ ${#paths[@]} -gt 0 ]]; then
  "$terramesh" traverse-eval "$map" --gt-mesh "$scene/ground_truth.ply" --path "${paths[@]}" --quiet \
    --report "$work/check.txt"
  for name in "${names[@]}"; do
    file="$work/plan_$name/path.csv"
    [[ ${code_of[$name]} == 0 ]] || continue
    valid=$(awk -v f="$file" '$1 == "path_valid" && $2 == f { print $3 }' "$work/check.txt")
    if [[ $valid != 1 ]]; then
      [[ ${outcome_of[$name]} == connected ]] && outcome_of[$name]="CONNECTED, INVALID ON THE TRUTH"
      says_of[$name]=$(awk -v f="$file" '$1 == "path_reason" && $2 == f { $1 = ""; $2 = ""; print }' "$work/check.txt" |
        head -c 200 | tr '|' ' ')
    fi
  done
fi

echo "| pair | truth | plan exit | outcome | plan or truth check says |"
echo "|---|---|---|---|---|"
for name in "${names[@]}"; do
  outcome=${outcome_of[$name]}
  count[$outcome]=$((${count[$outcome]:-0} + 1))
  echo "| $name | ${truth_of[$name]} | ${code_of[$name]} | $outcome | ${says_of[$name]} |"
done
echo
for outcome in "${!count[@]}"; do echo "- $outcome: ${count[$outcome]}"; done | sort
