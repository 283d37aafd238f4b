#!/usr/bin/env bash
# Installs what is missing, builds in Release and runs the whole test suite, then the same suite
# under the sanitizers and the bounded fuzzing. Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
phase() { echo "test.sh: $1 done at $((SECONDS - start)) s" >&2; }
scripts/install_deps.sh
phase "install"
scripts/build.sh
phase "Release build"
(cd build && ctest --output-on-failure -j "${TERRAMESH_JOBS:-$(nproc)}")
phase "Release suite"
# The whole suite again, built with clang under ASan + UBSan (Debug; the soak at 200 keyframes per
# mode; docs/reliability.md, "Sanitizers"). Its build also holds the libFuzzer targets, so the
# bounded fuzzing of every reader (docs/reliability.md, "Fuzzing") reuses it.
scripts/test_sanitized.sh
phase "sanitized build and suite"
TERRAMESH_FUZZ_SKIP_BUILD=1 scripts/fuzz.sh
phase "fuzzing"
