#!/usr/bin/env bash
# Builds terramesh with AddressSanitizer + UndefinedBehaviorSanitizer (clang, Debug: asserts on,
# -O1 -g, frame pointers; plus the libFuzzer targets) under build-sanitize/ and runs the whole test
# suite there; the first sanitizer report aborts its test. See docs/reliability.md, "Sanitizers".
# Usage: scripts/test_sanitized.sh [--build-only] [--target T]... [CTEST_ARGS...]
#   --build-only   configure and build, run no tests (scripts/fuzz.sh uses it)
#   --target T     build only target T (repeatable; default: everything)
# Environment: TERRAMESH_SANITIZE_DIR (build folder, default build-sanitize), TERRAMESH_JOBS,
# TERRAMESH_SANITIZE_CXX (default clang++), TERRAMESH_SANITIZE_SOAK_KEYFRAMES (default 200).
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${TERRAMESH_SANITIZE_DIR:-build-sanitize}"
jobs="${TERRAMESH_JOBS:-$(nproc)}"
cxx="${TERRAMESH_SANITIZE_CXX:-clang++}"
build_only=0
targets=()
ctest_args=()
while [ "$#" -gt 0 ]; do
  case "$1" in
    --build-only) build_only=1; shift ;;
    --target)
      if [ "$#" -lt 2 ]; then echo "test_sanitized.sh: --target needs a target name" >&2; exit 2; fi
      targets+=(--target "$2"); shift 2 ;;
    *) ctest_args+=("$1"); shift ;;
  esac
done
if ! command -v "$cxx" >/dev/null 2>&1; then
  echo "test_sanitized.sh: $cxx not found (scripts/install_deps.sh installs clang)" >&2
  exit 1
fi

launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$PWD"
fi
# The viewer's browser test and the package tests are left out (docs/reliability.md says why):
# no viewer bundle, no benchmarks.
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER="$cxx" "${launcher[@]}" \
  -DTERRAMESH_SANITIZE=address,undefined -DTERRAMESH_BUILD_FUZZERS=ON \
  -DTERRAMESH_BUILD_VIEWER=OFF -DTERRAMESH_BUILD_BENCHMARKS=OFF \
  -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE >/dev/null
cmake --build "$dir" -j "$jobs" "${targets[@]}"
if [ "$build_only" -eq 1 ]; then
  exit 0
fi

# Any report is fatal: abort (a core-less crash ctest records as a failure), leaks included, but
# for the third-party leaks listed with their evidence in cmake/lsan_suppressions.txt.
export ASAN_OPTIONS="abort_on_error=1:halt_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1:strict_init_order=1:detect_odr_violation=2"
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1"
source_dir="$PWD"
export LSAN_OPTIONS="suppressions=$source_dir/cmake/lsan_suppressions.txt:print_suppressions=0"
# Left out (docs/reliability.md, "Sanitizers"): the installed-package tests (they install and
# package the build, which says nothing about memory errors) and the CLI runs that repeat a whole
# pipeline on a generated stream (cli_mesh.SyntheticStreamTest, 222 s in Release alone, and EvalTest,
# cli_traverse's scenes, cli_evidence, cli_checkpoint's kill and signal runs: 60-120 s each here).
# Their libraries run sanitized in the unit tests, and the apps' paths in cli_mesh.KittiMeshTest,
# cli_generate, cli_hazards, cli_plan, cli_compare, cli_checkpoint.BadCheckpointTest and the
# bad-input tests. And the baseline modes' runs of the heaviest mesher tests (the same mesher code
# with other weights: their proposed-mode runs, the soaks and the mode tests keep them sanitized).
# And the tiles run on the one-node Slurm cluster (cli_tiles.TilesTest: every tile meshed twice;
# the tiling library runs sanitized in tiling_test, the CLI's paths in cli_tiles.TilesBadInputTest).
excluded='^(AllModes/(SceneReconstruction|Exactness)\..*/(romanoni15|litvinov13)|install\.|cli_mesh\.(SyntheticStreamTest|EvalTest)$|cli_traverse\.(StreetTest|GarageTest)$|cli_evidence\.|cli_checkpoint\.(StopSignalTest|KillAndResumeTest)$|cli_tiles\.TilesTest$)'
# Smaller data (docs/reliability.md, "Sanitizers"): the invariant soak with 200 keyframes per mode
# instead of 2,000/1,000; the Release suite runs the full count.
export TERRAMESH_SOAK_KEYFRAMES="${TERRAMESH_SANITIZE_SOAK_KEYFRAMES:-200}"
cd "$dir"
ctest --output-on-failure -j "$jobs" -E "$excluded" "${ctest_args[@]}"
