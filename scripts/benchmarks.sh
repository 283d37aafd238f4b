#!/usr/bin/env bash
# Regenerates the tables of the real-time targets (docs/benchmarks.md, "The targets in one run"):
# the keyframe update per stream against its floor, romanoni15 and (optionally) another build; the
# layer update per keyframe for every shipped robot on KITTI 00 and a generated street, and the
# full computation's faces per second; the trajectory evidence's share of the update; and LiDAR
# per scan (the ten shared KITTI 00 scans, optionally a generated street's). Prints markdown, with
# the machine, the date and the commit; the logs behind every number stay in OUT/logs.
#
# Usage: scripts/benchmarks.sh [OUT] [BEFORE_BUILD_DIR]      (default OUT: out/benchmarks)
#   BEFORE_BUILD_DIR: a build of another commit (with benchmarks/terramesh_latency_bench); its
#   latency bench runs on the same streams, alternating with this build's, and the table gains
#   the ratio of the medians (before / after).
# Env: TERRAMESH_BUILD (default build); TERRAMESH_SHARED_DIR (default ../shared);
#   TERRAMESH_BENCH_ROMANONI_KL=1 also runs romanoni15 over the whole KITTI-like stream (about 5
#   min; by default the speed-up is measured on the far-seeing streams and the first 300 KITTI-like
#   keyframes); TERRAMESH_BENCH_STREAMS (default "kl far far_seed2 far_dense") chooses the streams
#   of the first table; TERRAMESH_BENCH_LIDAR=0 skips the LiDAR scans; TERRAMESH_BENCH_LIDAR_SCANS=N
#   adds the first N scans of a generated LiDAR street (N=300: about 30 min). Streams are generated
#   once into OUT/streams and reused.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/benchmarks}
before=${2:-}
build=${TERRAMESH_BUILD:-build}
shared=${TERRAMESH_SHARED_DIR:-../shared}
terramesh=$build/apps/terramesh/terramesh
latency=$build/benchmarks/terramesh_latency_bench
for binary in "$terramesh" "$latency" "$build/benchmarks/terramesh_traversability_bench" \
  "$build/benchmarks/terramesh_evidence_bench"; do
  [[ -x $binary ]] || { echo "$binary: not built (scripts/build.sh builds every target)" >&2; exit 2; }
done
if [[ -n $before && ! -x $before/benchmarks/terramesh_latency_bench ]]; then
  echo "$before: expected a build directory with benchmarks/terramesh_latency_bench" >&2
  exit 2
fi
poses=$shared/data/kitti_poses/00.txt
[[ -f $poses ]] || { echo "$poses: missing (KITTI 00 poses, expected in TERRAMESH_SHARED_DIR)" >&2; exit 2; }
mkdir -p "$out/streams" "$out/logs" "$out/runs"
logs=$out/logs

# median FILE COLUMN [SCALE]: the median of a CSV column (by header name), times SCALE.
median() {
  awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next } c { print $c }' "$1" |
    sort -g | awk -v scale="${3:-1}" '{ v[n++] = $1 }
      END { if (!n) print "nan"; else printf "%.2f", scale * (n % 2 ? v[(n - 1) / 2] : (v[n / 2 - 1] + v[n / 2]) / 2) }'
}
# field LOG PATTERN N: the N-th word after PATTERN on the first line of LOG containing it.
field() { grep -m1 -- "$2" "$1" | sed "s|.*$2||" | awk -v n="$3" '{ print $n }'; }

# The streams: KITTI 00's trajectory at KITTI-like density, and two far-seeing streams (30 m range,
# half the matches), seeds 1 and 2 (the second not tuned on), and the denser far stream.
gen() {
  local name=$1; shift
  [[ -f $out/streams/$name/stream.tmstream ]] ||
    "$terramesh" generate street --preset kitti-like --kitti-poses "$poses" -o "$out/streams/$name" --quiet "$@"
}
gen kl
gen far --frames 0:4000 --max-range-m 30 --match-probability 0.5
gen far_seed2 --frames 0:4000 --max-range-m 30 --match-probability 0.5 --seed 2
gen far_dense --frames 0:4000 --max-range-m 30
[[ -f $out/streams/street200/stream.tmstream ]] ||
  "$terramesh" generate street --length-m 200 --seed 1 -o "$out/streams/street200" --quiet

echo "# Real-time targets, measured $(date -u +%Y-%m-%d) on $(scripts/machine.sh), Release build at" \
  "commit $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- . ':!out' || echo ' (with local changes)')"
echo
echo "## Keyframe update (thread CPU per keyframe, ms)"
echo
header="| stream | keyframes | median | p99 | floor median | update / floor | romanoni15 median | speed-up (total) |"
rule="|---|---|---|---|---|---|---|---|"
[[ -n $before ]] && { header+=" before median | before / after |"; rule+="---|---|"; }
echo "$header"
echo "$rule"
for stream in ${TERRAMESH_BENCH_STREAMS:-kl far far_seed2 far_dense}; do
  file=$out/streams/$stream/stream.tmstream
  if [[ -n $before ]]; then
    "$before/benchmarks/terramesh_latency_bench" "$file" --slowest 0 > "$logs/latency_${stream}_before.txt"
  fi
  "$latency" "$file" --floor --slowest 0 > "$logs/latency_$stream.txt"
  log=$logs/latency_$stream.txt
  cap=()
  [[ $stream == kl && ${TERRAMESH_BENCH_ROMANONI_KL:-0} != 1 ]] && cap=(--max-keyframes 300)
  "$terramesh" bench "$file" -o "$out/runs/bench_$stream" --modes proposed,romanoni15 "${cap[@]}" \
    > "$logs/bench_$stream.txt" 2>&1
  bench=$logs/bench_$stream.txt
  row="| $stream | $(field "$log" 'keyframes: ' 1) | $(field "$log" ' median ' 1) | $(field "$log" ' p99 ' 1)"
  row+=" | $(field "$log" 'floor CPU time per keyframe (ms): mean [0-9.]* median ' 1)"
  row+=" | $(field "$log" 'update / floor, medians: ' 1)"
  row+=" | $(awk '$1 == "romanoni15" && NF == 7 { print $3; exit }' "$bench")"
  row+=" | $(field "$bench" 'over romanoni15: .*Total ' 1)${cap:+ (first 300 keyframes)} |"
  if [[ -n $before ]]; then
    b=$(field "$logs/latency_${stream}_before.txt" ' median ' 1)
    row+=" $b | $(awk -v b="$b" -v a="$(field "$log" ' median ' 1)" 'BEGIN { printf "%.2f", b / a }') |"
  fi
  echo "$row"
done

echo
echo "## Layer update per keyframe (traversability_updates.csv, layer_update_s, ms)"
echo
echo "| robot | KITTI 00 (ORB-SLAM, 50 frames) median | street 200 m median |" \
  "full computation, faces per CPU s (built-in street 200 m) |"
echo "|---|---|---|---|"
kitti=$shared/data/kitti00_orbslam/slam_data_version0.1_KITTI00_50frames.json
for robot in small_wheeled legged car; do
  profile=traversability/robots/$robot.yaml
  "$terramesh" mesh "$kitti" --metres-per-unit 16.589 --robot "$profile" -o "$out/runs/kitti00_$robot" --quiet
  "$terramesh" mesh "$out/streams/street200/stream.tmstream" --robot "$profile" -o "$out/runs/street_$robot" --quiet
  full=$("$build/benchmarks/terramesh_traversability_bench" --benchmark_filter="BM_FullComputation/street200/$robot\$" \
    --benchmark_format=json 2> /dev/null | tee "$logs/full_$robot.json" |
    awk -F': ' '/"faces_per_s"/ { gsub(",", "", $2); printf "%.0f", $2; exit }')
  echo "| $robot | $(median "$out/runs/kitti00_$robot/traversability_updates.csv" layer_update_s 1000)" \
    "| $(median "$out/runs/street_$robot/traversability_updates.csv" layer_update_s 1000) | $full |"
done

echo
echo "## Trajectory evidence (terramesh_evidence_bench, built-in 200 m street, one run each way)"
echo
echo "| robot | mesher + layers, median without ms | with ms | ratio |"
echo "|---|---|---|---|"
for robot in small_wheeled car; do
  "$build/benchmarks/terramesh_evidence_bench" --rounds 1 --robot "traversability/robots/$robot.yaml" \
    > "$logs/evidence_$robot.txt"
  awk -v robot="$robot" -F'|' '$2 ~ /mesher \+ layers/ { printf "| %s |%s|%s|%s|\n", robot, $6, $7, $8; exit }' \
    "$logs/evidence_$robot.txt"
done

# lidar_row NAME INPUT [MESH ARGS...]: one LiDAR run with small_wheeled's layers, as a table row.
lidar_row() {
  local name=$1 input=$2 run=$out/runs/lidar_$1
  shift 2
  "$terramesh" mesh "$input" --robot traversability/robots/small_wheeled.yaml -o "$run" --memory-log --quiet "$@"
  # Per scan (one row per event in both files), the mesher's time plus the layers'.
  local both mem
  both=$(awk -F, 'FNR == 1 { for (i = 1; i <= NF; ++i) if ($i == "time_total_s" || $i == "layer_update_s") c = i; next }
    { s[FNR] += $c } END { for (k in s) print s[k] }' "$run/keyframes.csv" "$run/traversability_updates.csv" |
    sort -g | awk '{ v[n++] = $1 } END { printf "%.2f", n % 2 ? v[(n - 1) / 2] : (v[n / 2 - 1] + v[n / 2]) / 2 }')
  mem=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "rss_mib") c = i; next } { v[++n] = $c }
    END { printf "%.0f / %.0f", v[1], v[n] }' "$run/memory.csv")
  echo "| $name | $(median "$run/keyframes.csv" time_total_s)" \
    "| $(median "$run/traversability_updates.csv" layer_update_s) | $both | $mem |"
}

if [[ ${TERRAMESH_BENCH_LIDAR:-1} != 0 ]]; then
  echo
  echo "## LiDAR, defaults, small_wheeled (wall clock per scan, s)"
  echo
  echo "| scans | mesher median | layers median | mesher + layers median |" \
    "resident memory after the first / last scan, MiB |"
  echo "|---|---|---|---|---|"
  lidar_row kitti00 "$shared/data/kitti00_lidar" --poses "$poses"
  scans=${TERRAMESH_BENCH_LIDAR_SCANS:-0}
  if [[ $scans -gt 0 ]]; then
    street=$out/streams/lidar_street_$scans
    # The generator's scans are 0.8 m apart: a street long enough for them.
    [[ -d $street/lidar ]] || "$terramesh" generate street --length-m $((scans * 4 / 5 + 60)) --seed 1 --lidar \
      -o "$street" --quiet
    lidar_row "street_$scans" "$street/lidar" --poses "$street/lidar/poses.txt" --frames "0:$((scans - 1))"
  fi
fi
