#!/usr/bin/env bash
# Installs the Debian packages terramesh needs, only those missing. Needs root (or sudo).
set -euo pipefail

packages=(
  build-essential cmake git python3
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev libeigen3-dev nlohmann-json3-dev libpng-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libyaml-cpp-dev libgdal-dev gdal-bin libhdf5-dev libompl-dev ompl-demos liboctomap-dev libpcl-dev
  libcli11-dev libcpp-httplib-dev libnanoflann-dev libembree-dev robin-map-dev python3-numpy python3-matplotlib python3-yaml python3-h5py ccache
  chromium
  clang libclang-rt-dev
  # ROS 1 bags without ROS (datasets/src/rosbag_reader.cpp), and writing test bags from Python
  librosbag-storage-dev libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libtf2-msgs-dev
  pluginlib-dev librcpputils-dev libament-index-cpp-dev
  python3-rosbag python3-sensor-msgs python3-nav-msgs python3-geometry-msgs python3-tf2-msgs
  # Tiles meshed in parallel (scripts/slurm/): the one-node cluster of the tiles test
  slurm-wlm munge
)
# Node.js and npm (the viewer bundle, its browser tests), unless a Node.js with its own npm is there.
command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if [ "${#missing[@]}" -eq 0 ]; then
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo)
  else
    echo "install_deps.sh: missing packages (${missing[*]}) and not root; run as root" >&2
    exit 1
  fi
fi
echo "install_deps.sh: installing ${missing[*]}" >&2
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
