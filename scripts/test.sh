#!/usr/bin/env bash
# Installs what is missing, builds in Release and runs the whole test suite. Exits non-zero on any
# failure.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
(cd build && ctest --output-on-failure -j "${TERRAMESH_JOBS:-$(nproc)}")
# Bounded fuzzing of every reader under ASan + UBSan (docs/reliability.md, "Fuzzing"). The whole
# sanitized suite, scripts/test_sanitized.sh, is not in CI yet: its time is not measured.
scripts/fuzz.sh
