#!/usr/bin/env bash
# Layer updates on LiDAR scans, two builds against each other (docs/benchmarks.md, "Layer updates
# on LiDAR scans"): meshes the ten shared KITTI 00 scans and the first scans of a generated LiDAR
# street with `--robot`, once with each binary, alternating, and prints per run the layer updates
# (traversability_updates.csv: their sum, median and largest per scan, and how many were full
# rebuilds), the mesher's total (keyframes.csv), peak RSS, and whether traversability.ply is
# byte-identical to the first binary's of the same round.
#
# Usage: scripts/lidar_layer_updates.sh BEFORE_BINARY AFTER_BINARY [OUT] [STREET_SCANS]
#        (defaults: out/lidar_layers, 50)
# Env: TERRAMESH_ROUNDS (default 1) repeats each pair; TERRAMESH_ROBOT (default
# traversability/robots/small_wheeled.yaml); TERRAMESH_LIDAR_STREET, a generated LiDAR street to
# reuse (default OUT/street, generated with AFTER_BINARY: street, 300 m, seed 1, --lidar);
# TERRAMESH_SHARED_DIR (default ../shared). TERRAMESH_REUSE=1 keeps runs whose output exists.
set -euo pipefail
cd "$(dirname "$0")/.."
[[ $# -ge 2 ]] || { echo "usage: $0 BEFORE_BINARY AFTER_BINARY [OUT] [STREET_SCANS]" >&2; exit 2; }
before=$1
after=$2
out=${3:-out/lidar_layers}
street_scans=${4:-50}
for binary in "$before" "$after"; do
  [[ -x $binary ]] || { echo "$binary: expected an executable terramesh binary" >&2; exit 2; }
done
if [[ ! $street_scans =~ ^[1-9][0-9]*$ ]]; then
  echo "STREET_SCANS: expected a positive integer, got '$street_scans'" >&2
  exit 2
fi
shared=${TERRAMESH_SHARED_DIR:-../shared}
robot=${TERRAMESH_ROBOT:-traversability/robots/small_wheeled.yaml}
rounds=${TERRAMESH_ROUNDS:-1}
mkdir -p "$out"
street=${TERRAMESH_LIDAR_STREET:-$out/street}
if [[ ! -d $street/lidar ]]; then
  "$after" generate street --length-m 300 --seed 1 --lidar -o "$street" --quiet
fi

# run NAME BINARY INPUT [MESH ARGS...]: one mesh with the robot's layers, unless reused.
run() {
  local name=$1 binary=$2 input=$3
  shift 3
  local dir=$out/$name
  if [[ ${TERRAMESH_REUSE:-0} == 1 && -f $dir/traversability_updates.csv && -f $dir.rss ]]; then return; fi
  /usr/bin/time -f "%M" -o "$dir.rss" "$binary" mesh "$input" -o "$dir" --robot "$robot" --quiet "$@"
}

# row NAME REFERENCE: the table row of run NAME; REFERENCE is the run whose map it is compared with.
row() {
  /usr/bin/python3 - "$out/$1" "$1" "$out/$2" <<'EOF'
import csv, filecmp, statistics, sys
d, name, ref = sys.argv[1:4]
rows = [r for r in csv.DictReader(open(d + '/traversability_updates.csv')) if r['event'] != 'end']
layers = [float(r['layer_update_s']) for r in rows]
rebuilds = sum(int(r['full_rebuild']) for r in rows)
mesher = sum(float(r['time_total_s']) for r in csv.DictReader(open(d + '/keyframes.csv')))
rss_mib = int(open(d + '.rss').read().split()[-1]) / 1024
same = filecmp.cmp(d + '/traversability.ply', ref + '/traversability.ply', shallow=False)
print('| %s | %d | %.1f | %.2f | %.2f | %d | %.1f | %.0f | %s |' % (
    name, len(layers), sum(layers), statistics.median(layers), max(layers), rebuilds, mesher, rss_mib,
    'yes' if same else 'NO'))
EOF
}

columns=(run updates "layer updates s" "median s/scan" "max s/scan" "full rebuilds" "mesher s" "peak RSS MiB"
  "map as before's")
printf 'machine: %s; robot %s\n\n' "$(scripts/machine.sh)" "$robot"
printf '| %s ' "${columns[@]}"
printf '|\n'
printf '|---%.0s' "${columns[@]}"
printf '|\n'
last=$((street_scans - 1))
for round in $(seq "$rounds"); do
  for input in kitti street; do
    for label in before after; do
      binary=$before
      [[ $label == after ]] && binary=$after
      if [[ $input == kitti ]]; then
        run "${input}_${label}_r$round" "$binary" "$shared/data/kitti00_lidar" \
          --poses "$shared/data/kitti_poses/00.txt" --frames 1:10
      else
        run "${input}_${label}_r$round" "$binary" "$street/lidar" --poses "$street/lidar/poses.txt" --frames "0:$last"
      fi
      row "${input}_${label}_r$round" "${input}_before_r$round"
    done
  done
done
