#!/usr/bin/env bash
# Runs the viewer's browser tests after installing what they need: Debian's chromium (apt, if
# missing and root) and playwright-core from the pinned lockfile (npm ci in the build tree, never
# the source tree). Usage: run.sh SOURCE_DIR NPM_DIR TEST.mjs. Exits 77 (ctest: skipped) when
# they cannot be installed.
set -euo pipefail
source_dir=$1
npm_dir=$2
test_script=$3
if [ ! -x "${TERRAMESH_CHROMIUM:-/usr/bin/chromium}" ]; then
  if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "viewer tests: installing Debian's chromium" >&2
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium
  else
    echo "viewer tests: /usr/bin/chromium missing and not root; run scripts/install_deps.sh" >&2
    exit 77
  fi
fi
if ! command -v npm >/dev/null 2>&1; then
  echo "viewer tests: npm missing (apt-get install npm)" >&2
  exit 77
fi
node_major=$(node -p 'process.versions.node.split(".")[0]')
if [ "$node_major" -lt 20 ]; then
  echo "viewer tests: playwright-core needs Node.js >= 20, found $(node --version) (Debian 12 ships 18:" \
       "use Debian 13 or nodesource's nodejs 20)" >&2
  exit 1
fi
mkdir -p "$npm_dir"
if ! cmp -s "$source_dir/package-lock.json" "$npm_dir/package-lock.json" || [ ! -d "$npm_dir/node_modules/playwright-core" ]; then
  cp "$source_dir/package.json" "$source_dir/package-lock.json" "$npm_dir/"
  (cd "$npm_dir" && npm ci --no-audit --no-fund --loglevel=error)
fi
export TERRAMESH_VIEWER_TEST_MODULES="$npm_dir/node_modules"
exec node --test --test-concurrency=1 "$test_script"
