#!/usr/bin/env bash
# The Steiner lattice for LiDAR (docs/benchmarks.md, "The Steiner lattice for LiDAR"): meshes the
# ten shared KITTI 00 scans and the first scans of a generated LiDAR street with the mesher's 10 m
# lattice and with the 2 m one LiDAR inputs advise, alternating, and prints per run the mesher's
# median time per scan (keyframes.csv, wall clock), its map memory after the last scan, peak RSS,
# and accuracy and completeness against the scans themselves (terramesh eval --gt-lidar).
#
# Usage: scripts/lidar_lattice.sh [OUT] [STREET_SCANS]    (defaults: out/lidar_lattice, 50)
# Expects a Release build in build/ (or TERRAMESH_BUILD=dir) and ../shared/ beside the repository
# (or TERRAMESH_SHARED_DIR). TERRAMESH_LATTICE_ROUNDS (default 1) repeats each pair of runs.
set -euo pipefail
cd "$(dirname "$0")/.."
terramesh=${TERRAMESH_BUILD:-build}/apps/terramesh/terramesh
shared=${TERRAMESH_SHARED_DIR:-../shared}
out=${1:-out/lidar_lattice}
street_scans=${2:-50}
rounds=${TERRAMESH_LATTICE_ROUNDS:-1}
[[ -x $terramesh ]] || { echo "no $terramesh: build first (cmake --build build -j2)" >&2; exit 2; }
[[ $street_scans =~ ^[1-9][0-9]*$ ]] || { echo "STREET_SCANS: expected a positive integer, got '$street_scans'" >&2; exit 2; }
kitti=$shared/data/kitti00_lidar
poses=$shared/data/kitti_poses/00.txt
mkdir -p "$out"
street=$out/street
if [[ ! -d $street/lidar ]]; then
  "$terramesh" generate street --length-m 300 --seed 1 --lidar -o "$street" --quiet
fi

# run NAME INPUT FRAMES EVAL_POSES EVAL_FRAMES [MESH ARGS...]: one mesh and its scores, one line.
run() {
  local name=$1 input=$2 frames=$3 eval_poses=$4 eval_frames=$5
  shift 5
  local dir=$out/$name
  /usr/bin/time -f "%M" -o "$dir.rss" "$terramesh" mesh "$input" $frames -o "$dir" --quiet "$@"
  "$terramesh" eval "$dir/mesh.ply" --gt-lidar "$input" --poses "$eval_poses" --frames "$eval_frames" \
    --report "$dir.eval.txt" --quiet > /dev/null
  /usr/bin/python3 - "$dir" "$name" <<'EOF'
import csv, statistics, sys
d, name = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(d + '/keyframes.csv')))
times = [float(r['time_total_s']) for r in rows]
scores = dict(line.split()[:2] for line in open(d + '.eval.txt') if len(line.split()) == 2)
rss_mib = int(open(d + '.rss').read().split()[-1]) / 1024
print('| %s | %d | %.2f | %.2f | %.0f | %.0f | %s | %s | %s | %s |' % (
    name, len(times), statistics.median(times), times[-1], float(rows[-1]['map_bytes']) / 2**20, rss_mib,
    scores['accuracy_within_0.20m'], scores['accuracy_within_0.25m'],
    scores['completeness_within_0.20m'], scores['completeness_within_0.25m']))
EOF
}

echo "machine: $(scripts/machine.sh); commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo
echo "| run | scans | mesher s/scan, median | last scan s | map MiB | peak RSS MiB | accuracy <= 0.2 m |" \
  "accuracy <= 0.25 m | completeness <= 0.2 m | completeness <= 0.25 m |"
echo "|---|---|---|---|---|---|---|---|---|---|"
last=$((street_scans - 1))
for round in $(seq "$rounds"); do
  run "kitti_10m_r$round" "$kitti" "--poses $poses" "$poses" 1:10 --steiner-step-m 10
  run "kitti_2m_r$round" "$kitti" "--poses $poses" "$poses" 1:10
  run "street_10m_r$round" "$street/lidar" "--frames 0:$last" "$street/lidar/poses.txt" "0:$last" --steiner-step-m 10
  run "street_2m_r$round" "$street/lidar" "--frames 0:$last" "$street/lidar/poses.txt" "0:$last"
done
