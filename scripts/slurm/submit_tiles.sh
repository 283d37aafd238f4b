#!/usr/bin/env bash
# Submits the tiles of a plan to Slurm: a job array of scripts/slurm/tiles.sbatch (one task per
# tile), and `terramesh tiles merge PLAN` as a job that runs once every tile succeeded
# (--dependency=afterok). Prints the two job ids. See docs/tiles.md, "On Slurm".
# Usage: TERRAMESH=/path/to/terramesh submit_tiles.sh [--wait] [--max-parallel N] STREAM PLAN [MESH OPTIONS...]
#   --wait            return when the merge job has ended, with its exit status (sbatch --wait)
#   --max-parallel N  run at most N tiles at once (the array's %N)
# Slurm writes the jobs' output to slurm-tiles-<job>_<task>.out beside the plan.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
wait=()
parallel=""
while [ "$#" -gt 0 ]; do
  case "$1" in
    --wait) wait=(--wait); shift ;;
    --max-parallel)
      if [ "$#" -lt 2 ]; then echo "submit_tiles.sh: --max-parallel needs a number" >&2; exit 2; fi
      parallel="%$2"; shift 2 ;;
    *) break ;;
  esac
done
if [ "$#" -lt 2 ]; then
  echo "usage: TERRAMESH=/path/to/terramesh $0 [--wait] [--max-parallel N] STREAM PLAN [MESH OPTIONS...]" >&2
  exit 2
fi
if [ -z "${TERRAMESH:-}" ] || [ ! -x "$TERRAMESH" ]; then
  echo "submit_tiles.sh: set TERRAMESH to the terramesh executable (got \"${TERRAMESH:-}\")" >&2
  exit 2
fi
stream="$(realpath "$1")"
plan="$(realpath "$2")"
shift 2
tiles="$(python3 -c 'import json, sys; print(len(json.load(open(sys.argv[1]))["tiles"]))' "$plan" 2>/dev/null)" || {
  echo "submit_tiles.sh: $plan: not a tile plan (terramesh tiles plan writes one)" >&2
  exit 2
}
log_dir="$(dirname "$plan")"
export TERRAMESH
array_id="$(sbatch --parsable --array="0-$((tiles - 1))$parallel" --chdir="$log_dir" \
  --output="$log_dir/slurm-tiles-%A_%a.out" "$here/tiles.sbatch" "$stream" "$plan" "$@")"
array_id="${array_id%%;*}"
echo "tiles: job array $array_id ($tiles tasks)"
merge_id="$(sbatch --parsable "${wait[@]}" --dependency="afterok:$array_id" --kill-on-invalid-dep=yes \
  --job-name=terramesh-merge --chdir="$log_dir" --output="$log_dir/slurm-tiles-merge-%j.out" \
  --wrap="$(printf '%q ' "$TERRAMESH" tiles merge "$plan")")"
echo "merge: job ${merge_id%%;*}"
