#!/usr/bin/env bash
# Configures and builds terramesh in Release under build/ (used by demo.sh and test.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${TERRAMESH_JOBS:-$(nproc)}"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j "$jobs"
