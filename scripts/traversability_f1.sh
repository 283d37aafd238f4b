#!/usr/bin/env bash
# Traversability maps against ground truth: for the synthetic street, offroad and garage scenes
# (seed 1) and every shipped robot profile (traversability/robots/*.yaml), generates the scene,
# meshes it with traversability layers (`terramesh mesh --robot`), scores the map against the
# generator's labelled ground truth (`terramesh traverse-eval --gt-mesh`) and prints a markdown
# table, the swept footprint and the free ground over a drop (scripts/free_over_drops.py); then the
# road under the camera path on real KITTI 00 (ORB-SLAM, 16.589 m per unit), and the
# swept footprint there against the Velodyne ground.
# Expects a Release build in build/ (or TERRAMESH_BUILD=dir) and ../shared/ beside the
# repository. Writes under out/traversability_f1/ (or TERRAMESH_F1_OUT); with TERRAMESH_REUSE=1,
# scenes and maps already there are not made again (only scored). TERRAMESH_F1_SCENES and
# TERRAMESH_F1_ROBOTS (space-separated names) restrict the run, e.g. to split it over two
# processes; TERRAMESH_F1_SEEDS (default 1) lists the scene seeds; TERRAMESH_F1_MESH_ARGS adds
# arguments to every `terramesh mesh` (e.g. --no-trajectory-evidence); TERRAMESH_F1_KITTI=0 skips
# KITTI 00.
set -euo pipefail
cd "$(dirname "$0")/.."
terramesh=${TERRAMESH_BUILD:-build}/apps/terramesh/terramesh
shared=${TERRAMESH_SHARED_DIR:-../shared}
out=${TERRAMESH_F1_OUT:-out/traversability_f1}
mkdir -p "$out"
# The generator's camera rig is not KITTI's: for the synthetic scenes each profile is used without
# its sensor mounting (car.yaml gives KITTI's 1.65 m), so the runs estimate it from the data.
rigless="$out/profiles_without_mounting"
mkdir -p "$rigless"
scenes=(${TERRAMESH_F1_SCENES:-street offroad garage hazards})
seeds=(${TERRAMESH_F1_SEEDS:-1})
mesh_args=(${TERRAMESH_F1_MESH_ARGS:-})
robots=()
for robot_file in traversability/robots/*.yaml; do
  if [[ -z ${TERRAMESH_F1_ROBOTS:-} || " $TERRAMESH_F1_ROBOTS " == *" $(basename "$robot_file" .yaml) "* ]]; then
    robots+=("$robot_file")
  fi
done
if [[ ${#robots[@]} == 0 || ! -e "${robots[0]}" ]]; then
  echo "no robot profiles in traversability/robots/ (or none named in TERRAMESH_F1_ROBOTS)" >&2
  exit 1
fi

# One markdown row from a traverse-eval report.
row() {
  awk -v scene="$1" -v robot="$2" '
    { v[$1] = $2 }
    END {
      printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", scene, robot,
        v["precision"], v["recall"], v["f1"], v["coverage"], v["free_coverage"], v["unknown_fraction"],
        v["uncertain_fraction"], v["scored_m2"], v["truth_traversable_m2"]
    }' "$3"
}

# The worst-classified truth labels of a report: scored area of each label and its free share.
labels() {
  awk '
    /^label_[a-z]+_(free|lethal|unknown|uncertain)_m2 / {
      split($1, part, "_"); area[part[2], part[3]] = $2; names[part[2]] = 1
    }
    END {
      for (n in names) {
        total = area[n, "free"] + area[n, "lethal"] + area[n, "unknown"] + area[n, "uncertain"]
        if (total <= 0) continue
        printf "%s %.1f m2 (free %.2f lethal %.2f unknown %.2f uncertain %.2f); ", n, total,
          area[n, "free"] / total, area[n, "lethal"] / total, area[n, "unknown"] / total, area[n, "uncertain"] / total
      }
      printf "\n"
    }' "$1"
}

echo "## Synthetic scenes (seeds ${seeds[*]}): map faces within 0.5 m of the truth"
echo
echo "| scene | robot | precision | recall | F1 | coverage | free coverage | unknown fraction | uncertain fraction | scored m2 | truth traversable m2 |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for seed in "${seeds[@]}"; do
  for base in "${scenes[@]}"; do
    scene=$base
    [[ $seed == 1 ]] || scene="${base}_seed$seed"
    [[ ${TERRAMESH_REUSE:-0} == 1 && -f "$out/$scene/ground_truth.ply" ]] ||
      "$terramesh" generate "$base" -o "$out/$scene" --seed "$seed" --quiet
    for robot_file in "${robots[@]}"; do
      robot=$(basename "$robot_file" .yaml)
      map="$out/${scene}_$robot"
      grep -v -E '^(sensor_height_m|sensor_pose_in_base)' "$robot_file" > "$rigless/$robot.yaml"
      [[ ${TERRAMESH_REUSE:-0} == 1 && -f "$map/traversability.ply" ]] ||
        "$terramesh" mesh "$out/$scene/stream.tmstream" --robot "$rigless/$robot.yaml" -o "$map" --quiet "${mesh_args[@]}"
      "$terramesh" traverse-eval "$map" --gt-mesh "$out/$scene/ground_truth.ply" \
        --report "$out/${scene}_$robot.txt" --quiet
      row "$scene" "$robot" "$out/${scene}_$robot.txt"
    done
  done
done

# The robot's swept footprint on each synthetic scene: the map under the camera path (the true pose
# of every 10 Hz frame, frames.txt of terramesh generate; the keyframes of the stream for a scene
# generated without it), within the footprint's half-width (disc: radius) of it, and how far its
# free part lies from the truth; the share of it the truth does not rule out for the robot (all
# but ground where the truth says its footprint does not fit: centred off the path, it reaches
# beyond where the body swept) and the free share of that part. The camera height is the one the
# run's mesh.ply records (its estimate from the data). "underfoot": the same strip by ground area,
# each 0.1 m column taking the highest map face in the band that does not face down (none: no
# surface there).
echo
echo "## Synthetic scenes: the swept footprint (map under the path, within the robot's half-width)"
echo
echo "| scene | robot | free | lethal | unknown | uncertain | free: truth distance median m | p90 m | truth: robot fits | free where it fits | underfoot: free | lethal | uncertain | none | free where it fits |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
half_width() {
  awk '/^ *radius_m:/ { r = $2 } /^ *width_m:/ { w = $2 / 2 } END { print (w > 0 ? w : r) }' "$1"
}
for seed in "${seeds[@]}"; do
  for base in ${TERRAMESH_F1_SCENES:-street offroad garage hazards}; do
    scene=$base
    [[ $seed == 1 ]] || scene="${base}_seed$seed"
    for robot_file in "${robots[@]}"; do
      robot=$(basename "$robot_file" .yaml)
      map="$out/${scene}_$robot"
      path="$out/$scene/frames.txt"
      [[ -f $path ]] || path="$out/$scene/stream.tmstream"
      "$terramesh" traverse-eval "$map" --gt-mesh "$out/$scene/ground_truth.ply" \
        --road-under-path "$path" \
        --lateral-m "$(half_width "$robot_file")" --report "$out/${scene}_${robot}_swept.txt" --quiet
      awk -v scene="$scene" -v robot="$robot" '{ v[$1] = $2 } END {
          printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", scene, robot,
            v["road_free_fraction"], v["road_lethal_fraction"], v["road_unknown_fraction"], v["road_uncertain_fraction"],
            v["road_free_truth_distance_median_m"], v["road_free_truth_distance_p90_m"],
            v["road_truth_fits_fraction"], v["road_free_where_truth_fits_fraction"],
            v["road_underfoot_free_fraction"], v["road_underfoot_lethal_fraction"],
            v["road_underfoot_uncertain_fraction"], v["road_underfoot_none_fraction"],
            v["road_underfoot_free_where_truth_fits_fraction"]
        }' "$out/${scene}_${robot}_swept.txt"
    done
  done
done

scenes=()
for seed in "${seeds[@]}"; do
  for base in ${TERRAMESH_F1_SCENES:-street offroad garage hazards}; do
    if [[ $seed == 1 ]]; then scenes+=("$base"); else scenes+=("${base}_seed$seed"); fi
  done
done

# Free ground over a drop the robot cannot step down (scripts/free_over_drops.py): the mesh spanning
# a pit, a ditch or a ledge at the rim's height, which precision within 0.5 m of the truth misses.
python3=/usr/bin/python3
[ -x "$python3" ] || python3=python3
echo
echo "## Synthetic scenes: free ground over a drop the robot cannot step down"
echo
echo "| scene | robot | free m2 | over a drop m2 | share |"
echo "|---|---|---|---|---|"
for scene in "${scenes[@]}"; do
  for robot_file in "${robots[@]}"; do
    robot=$(basename "$robot_file" .yaml)
    "$python3" scripts/free_over_drops.py "$out/${scene}_$robot" "$out/$scene/ground_truth.ply" |
      awk -v scene="$scene" -v robot="$robot" '{ v[$1] = $2 } END {
          printf "| %s | %s | %s | %s | %s |\n", scene, robot, v["free_m2"], v["free_over_drop_m2"],
            v["free_over_drop_fraction"]
        }'
  done
done
echo
echo "Per-label map area (nearest truth label) and its free / lethal / unknown shares:"
echo
for scene in "${scenes[@]}"; do
  for robot_file in "${robots[@]}"; do
    robot=$(basename "$robot_file" .yaml)
    echo "- $scene / $robot: $(labels "$out/${scene}_$robot.txt")"
  done
done

if [[ ${TERRAMESH_F1_KITTI:-1} == 0 ]]; then exit 0; fi

# KITTI 00: the road under the ORB-SLAM keyframe path, 1.65 m below the camera, 1.5 m each side.
echo
echo "## KITTI 00 (ORB-SLAM, 50 frames): the road under the camera path"
echo
echo "| robot | free | lethal | unknown | uncertain | road m2 | path m |"
echo "|---|---|---|---|---|---|---|"
stream=$shared/data/kitti00_orbslam/slam_data_version0.1_KITTI00_50frames.json
for robot_file in "${robots[@]}"; do
  robot=$(basename "$robot_file" .yaml)
  map="$out/kitti00_$robot"
  [[ ${TERRAMESH_REUSE:-0} == 1 && -f "$map/traversability.ply" ]] ||
    "$terramesh" mesh "$stream" --robot "$robot_file" --metres-per-unit 16.589 -o "$map" --quiet "${mesh_args[@]}"
  "$terramesh" traverse-eval "$map" --road-under-path "$stream" --report "$out/kitti00_$robot.txt" --quiet
  awk -v robot="$robot" '{ v[$1] = $2 } END {
      printf "| %s | %s | %s | %s | %s | %.1f | %s |\n", robot, v["road_free_fraction"], v["road_lethal_fraction"],
        v["road_unknown_fraction"], v["road_uncertain_fraction"],
        v["road_free_m2"] + v["road_lethal_m2"] + v["road_unknown_m2"] + v["road_uncertain_m2"], v["path_length_m"]
    }' "$out/kitti00_$robot.txt"
done

# KITTI 00 against the LiDAR ground: the Velodyne returns of frames 1-10 (merged, in the KITTI
# ground-truth frame; ICP similarity to the ORB-SLAM map) within the robot's half-width of the path
# and 1.65 m +- 0.5 m below it are the true road; each takes the map face straight above or below.
lidar=$shared/data/kitti00_lidar
echo
echo "## KITTI 00: the swept footprint against the LiDAR ground (Velodyne frames 1-10)"
echo
echo "| robot | half-width m | LiDAR points | path covered m | free | lethal | unknown | uncertain | no surface | free: height median m | p90 m |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for robot_file in "${robots[@]}"; do
  robot=$(basename "$robot_file" .yaml)
  half=$(half_width "$robot_file")
  "$terramesh" traverse-eval "$out/kitti00_$robot" --road-under-path "$stream" --lateral-m "$half" \
    --lidar-ground "$lidar/lidar_gt_frames01-10_cam0world_vox10cm.ply" --lidar-sim3 "$lidar/piazza_sim3_to_gt_icp.txt" \
    --report "$out/kitti00_${robot}_lidar.txt" --quiet
  awk -v robot="$robot" -v half="$half" '{ v[$1] = $2 } END {
      printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", robot, half, v["lidar_ground_points"],
        v["lidar_covered_path_m"], v["lidar_free_fraction"], v["lidar_lethal_fraction"], v["lidar_unknown_fraction"],
        v["lidar_uncertain_fraction"], v["lidar_missing_fraction"], v["lidar_free_height_median_m"],
        v["lidar_free_height_p90_m"]
    }' "$out/kitti00_${robot}_lidar.txt"
done
