#!/usr/bin/env bash
# One line naming this machine for benchmark tables: CPU model, cores, memory.
set -euo pipefail
echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(nproc) cores," \
  "$(free -g | awk '/Mem:/ {print $2}') GiB"
