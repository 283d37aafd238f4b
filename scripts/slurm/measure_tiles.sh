#!/usr/bin/env bash
# Measures the tiles of docs/tiles.md on a synthetic street: the untiled run, the plan's tiles meshed
# serially and through Slurm (a one-node cluster on localhost, scripts/slurm/local_cluster.py), wall
# time and peak memory, and the class agreement across borders. Prints a Markdown table. Needs root,
# slurm-wlm and munge. Writes only under a temporary folder.
# Usage: scripts/slurm/measure_tiles.sh BUILD_DIR [LENGTH_M TILE_M OVERLAP_M]
# Environment: TERRAMESH_SLURM_TASKS lists how many tiles Slurm runs at once, one run each (default
# "2"; the node gets as many CPUs as the largest); TERRAMESH_MEASURE_SERIAL=0 skips the untiled run,
# the serial one and the border check (a long street's untiled run does not fit in memory).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(realpath "${1:?usage: $0 BUILD_DIR [LENGTH_M TILE_M OVERLAP_M]}")"
length="${2:-140}"
tile="${3:-65}"
overlap="${4:-10}"
tasks=(${TERRAMESH_SLURM_TASKS:-2})
cpus=$(printf '%s\n' "${tasks[@]}" | sort -n | tail -1)
serial_run=${TERRAMESH_MEASURE_SERIAL:-1}
bin="$build/apps/terramesh/terramesh"
robot="$here/../../traversability/robots/small_wheeled.yaml"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
timed() {  # timed NAME COMMAND...: wall seconds and peak resident memory (MiB) into $work/NAME.time
  local name="$1"
  shift
  /usr/bin/time -f "%e %M" -o "$work/$name.time" "$@" >"$work/$name.out"
}
seconds_since() {  # seconds_since START: wall seconds from START (date +%s.%N) to now
  python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" "$1" "$(date +%s.%N)"
}
ratio() { python3 -c "import sys; print(f'{float(sys.argv[1]) / float(sys.argv[2]):.2f}')" "$1" "$2"; }
"$bin" generate street --length-m "$length" --seed 1 --outlier-fraction 0 -o "$work/data" --quiet
stream="$work/data/stream.tmstream"
timed plan "$bin" tiles plan "$stream" --tile-m "$tile" --overlap-m "$overlap" --robot "$robot" -o "$work/plan.json"
tiles=$(python3 -c 'import json, sys; print(len(json.load(open(sys.argv[1]))["tiles"]))' "$work/plan.json")
reference=""
if [[ $serial_run != 0 ]]; then
  timed untiled "$bin" mesh "$stream" --robot "$robot" -o "$work/untiled" --quiet
  start=$(date +%s.%N)
  "$bin" tiles plan "$stream" --tile-m "$tile" --overlap-m "$overlap" --robot "$robot" \
    -o "$work/serial/plan.json" --quiet
  for ((i = 0; i < tiles; i++)); do
    timed "tile$i" "$bin" mesh "$stream" --tile "$work/serial/plan.json:$i" --robot "$robot" --quiet
  done
  timed merge "$bin" tiles merge "$work/serial/plan.json"
  serial=$(seconds_since "$start")
  "$bin" tiles merge "$work/serial/plan.json" --check-borders >"$work/borders.out"
  reference="$work/serial"
fi
# Two times per Slurm run: from submitting the array to the end of the merge job (Slurm's own
# SubmitTime and EndTime, whole seconds), and until `sbatch --wait` returned (it polls the job's
# state at growing intervals, so it returns later).
for n in "${tasks[@]}"; do
  run="$work/slurm$n"
  "$bin" tiles plan "$stream" --tile-m "$tile" --overlap-m "$overlap" --robot "$robot" -o "$run/plan.json" --quiet
  python3 "$here/local_cluster.py" --cpus "$cpus" -- bash -c '
    start=$(date +%s.%N)
    TERRAMESH="$1" "$2/submit_tiles.sh" --wait --max-parallel "$7" "$3" "$4" --robot "$5" >"$6.ids"
    python3 -c "import sys; print(f\"{float(sys.argv[2]) - float(sys.argv[1]):.2f}\")" "$start" "$(date +%s.%N)" >"$6"
    array=$(sed -n "s/^tiles: job array \([0-9]*\).*/\1/p" "$6.ids")
    scontrol show job "$array" | grep -o "SubmitTime=[^ ]*" | head -1 >"$6.jobs"
    merge=$(sed -n "s/^merge: job \([0-9]*\).*/\1/p" "$6.ids")
    scontrol show job "$merge" | grep -o "EndTime=[^ ]*" >>"$6.jobs"
  ' _ "$bin" "$here" "$stream" "$run/plan.json" "$robot" "$run.seconds" "$n"
  python3 -c '
import datetime, sys
times = dict(line.strip().split("=", 1) for line in open(sys.argv[1]))
parse = lambda text: datetime.datetime.fromisoformat(text)
print(int((parse(times["EndTime"]) - parse(times["SubmitTime"])).total_seconds()))' "$run.seconds.jobs" >"$run.jobs"
  reference=${reference:-$run}
done
identical=yes
for n in "${tasks[@]}"; do
  for file in $(cd "$reference" && find tiles.json overview tile_*/map tile_*/tile.json -type f | sort); do
    cmp -s "$reference/$file" "$work/slurm$n/$file" || identical="no ($n at once: $file)"
  done
done
echo "street ${length} m (seed 1), tiles of ${tile} m, overlap ${overlap} m: ${tiles} tiles;" \
  "$(nproc) cores, a Slurm node of ${cpus} CPUs"
echo
echo "| run | wall s | peak memory MiB |"
echo "|---|---|---|"
read -r plan_s plan_kb <"$work/plan.time"
echo "| \`tiles plan\` | $plan_s | $((plan_kb / 1024)) |"
if [[ $serial_run != 0 ]]; then
  read -r untiled_s untiled_kb <"$work/untiled.time"
  echo "| untiled \`mesh --robot\` | $untiled_s | $((untiled_kb / 1024)) |"
  for ((i = 0; i < tiles; i++)); do
    read -r s kb <"$work/tile$i.time"
    echo "| tile $i (\`mesh --tile\`, $(grep -o "[0-9]* keyframes, [0-9]* points" "$work/plan.out" | sed -n "$((i + 1))p")) | $s | $((kb / 1024)) |"
  done
  read -r merge_s merge_kb <"$work/merge.time"
  echo "| merge | $merge_s | $((merge_kb / 1024)) |"
  echo "| serial: plan, $tiles tiles one after another, merge | $serial | |"
fi
first=""
for n in "${tasks[@]}"; do
  jobs=$(cat "$work/slurm$n.jobs")
  first=${first:-$jobs}
  echo "| Slurm, $n at once: array submitted to merge ended (Slurm's times) | $jobs | |"
  echo "| Slurm, $n at once: until \`submit_tiles.sh --wait\` returned | $(cat "$work/slurm$n.seconds") | |"
done
echo
for n in "${tasks[@]:1}"; do
  echo "- Slurm's times, ${tasks[0]} at once over $n at once: $(ratio "$first" "$(cat "$work/slurm$n.jobs")")"
done
echo "- merged files byte-identical across runs: $identical"
[[ $serial_run == 0 ]] || grep '^border' "$work/borders.out" | sed 's/^/- /'
