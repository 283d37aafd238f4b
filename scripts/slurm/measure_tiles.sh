#!/usr/bin/env bash
# Measures the tiles of docs/tiles.md on a synthetic street: the untiled run, a 4-tile plan meshed
# serially and through Slurm (a one-node cluster on localhost with 2 CPUs, scripts/slurm/
# local_cluster.py), wall time and peak memory, and the class agreement across borders. Prints a
# Markdown table. Needs root, slurm-wlm and munge. Writes only under a temporary folder.
# Usage: scripts/slurm/measure_tiles.sh BUILD_DIR [LENGTH_M TILE_M OVERLAP_M]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(realpath "${1:?usage: $0 BUILD_DIR [LENGTH_M TILE_M OVERLAP_M]}")"
length="${2:-140}"
tile="${3:-65}"
overlap="${4:-10}"
bin="$build/apps/terramesh/terramesh"
robot="$here/../../traversability/robots/small_wheeled.yaml"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
timed() {  # timed NAME COMMAND...: wall seconds and peak resident memory (MiB) into $work/NAME.time
  local name="$1"
  shift
  /usr/bin/time -f "%e %M" -o "$work/$name.time" "$@" >"$work/$name.out"
}
"$bin" generate street --length-m "$length" --seed 1 --outlier-fraction 0 -o "$work/data" --quiet
stream="$work/data/stream.tmstream"
timed untiled "$bin" mesh "$stream" --robot "$robot" -o "$work/untiled" --quiet
start=$(date +%s.%N)
timed plan "$bin" tiles plan "$stream" --tile-m "$tile" --overlap-m "$overlap" --robot "$robot" -o "$work/serial/plan.json"
tiles=$(python3 -c 'import json, sys; print(len(json.load(open(sys.argv[1]))["tiles"]))' "$work/serial/plan.json")
for ((i = 0; i < tiles; i++)); do
  timed "tile$i" "$bin" mesh "$stream" --tile "$work/serial/plan.json:$i" --robot "$robot" --quiet
done
timed merge "$bin" tiles merge "$work/serial/plan.json"
serial=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" "$start" "$(date +%s.%N)")
"$bin" tiles plan "$stream" --tile-m "$tile" --overlap-m "$overlap" --robot "$robot" -o "$work/slurm/plan.json" --quiet
# Two times: from submitting the array to the end of the merge job (Slurm's own SubmitTime and
# EndTime, whole seconds), and until `sbatch --wait` returned (it polls the job's state at growing
# intervals, so it returns later).
python3 "$here/local_cluster.py" --cpus 2 -- bash -c '
  start=$(date +%s.%N)
  TERRAMESH="$1" "$2/submit_tiles.sh" --wait "$3" "$4" --robot "$5" >"$6.ids"
  python3 -c "import sys; print(f\"{float(sys.argv[2]) - float(sys.argv[1]):.2f}\")" "$start" "$(date +%s.%N)" >"$6"
  array=$(sed -n "s/^tiles: job array \([0-9]*\).*/\1/p" "$6.ids")
  scontrol show job "$array" | grep -o "SubmitTime=[^ ]*" | head -1 >"$6.jobs"
  merge=$(sed -n "s/^merge: job \([0-9]*\).*/\1/p" "$6.ids")
  scontrol show job "$merge" | grep -o "EndTime=[^ ]*" >>"$6.jobs"
' _ "$bin" "$here" "$stream" "$work/slurm/plan.json" "$robot" "$work/slurm.seconds"
slurm_jobs=$(python3 -c '
import datetime, sys
times = dict(line.strip().split("=", 1) for line in open(sys.argv[1]))
parse = lambda text: datetime.datetime.fromisoformat(text)
print(int((parse(times["EndTime"]) - parse(times["SubmitTime"])).total_seconds()))' "$work/slurm.seconds.jobs")
identical=yes
for file in $(cd "$work/serial" && find tiles.json overview tile_*/map tile_*/tile.json -type f | sort); do
  cmp -s "$work/serial/$file" "$work/slurm/$file" || identical="no ($file)"
done
"$bin" tiles merge "$work/serial/plan.json" --check-borders >"$work/borders.out"
read -r untiled_s untiled_kb <"$work/untiled.time"
echo "street ${length} m (seed 1), tiles of ${tile} m, overlap ${overlap} m: ${tiles} tiles"
echo
echo "| run | wall s | peak memory MiB |"
echo "|---|---|---|"
echo "| untiled \`mesh --robot\` | $untiled_s | $((untiled_kb / 1024)) |"
for ((i = 0; i < tiles; i++)); do
  read -r s kb <"$work/tile$i.time"
  echo "| tile $i (\`mesh --tile\`, $(grep -o "[0-9]* keyframes, [0-9]* points" "$work/plan.out" | sed -n "$((i + 1))p")) | $s | $((kb / 1024)) |"
done
read -r merge_s merge_kb <"$work/merge.time"
echo "| merge | $merge_s | $((merge_kb / 1024)) |"
echo "| serial: plan, $tiles tiles one after another, merge | $serial | |"
echo "| Slurm, 2 tasks at once: array submitted to merge ended (Slurm's times) | $slurm_jobs | |"
echo "| Slurm, 2 tasks at once: until \`submit_tiles.sh --wait\` returned | $(cat "$work/slurm.seconds") | |"
echo
echo "merged files byte-identical, serial vs Slurm: $identical"
grep '^border' "$work/borders.out" | sed 's/^/- /'
