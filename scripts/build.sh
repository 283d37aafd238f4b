#!/usr/bin/env bash
# Configures and builds terramesh in Release under build/ (used by demo.sh and test.sh).
# Usage: scripts/build.sh [--target T]... [CMAKE_OPTIONS...]
#   --target T   build only target T and what it needs (repeatable; default: everything), e.g.
#                `--target terramesh` for the CLI alone. Other arguments go to the configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${TERRAMESH_JOBS:-$(nproc)}"
targets=()
configure=()
while [ "$#" -gt 0 ]; do
  case "$1" in
    --target)
      if [ "$#" -lt 2 ]; then echo "build.sh: --target needs a target name" >&2; exit 2; fi
      targets+=(--target "$2")
      shift 2
      ;;
    --target=*)
      targets+=(--target "${1#--target=}")
      shift
      ;;
    *)
      configure+=("$1")
      shift
      ;;
  esac
done
launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  # Paths relative to the checkout: clones in other folders share the compiler cache.
  export CCACHE_BASEDIR="$PWD"
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "${configure[@]}" >/dev/null
cmake --build build -j "$jobs" "${targets[@]}"
