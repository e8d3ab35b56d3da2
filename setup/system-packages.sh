#!/usr/bin/env bash
# Installs the Debian packages ParaDyn builds against, when they are missing.
# As root it runs apt-get; otherwise it lists what to install and fails.
set -euo pipefail
packages=(gfortran libopenmpi-dev openmpi-bin libhdf5-openmpi-dev cmake make pkg-config python3-venv python3-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -eq 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
else
  echo "setup: these Debian packages are missing: ${missing[*]}" >&2
  echo "setup: install them with: sudo apt-get install ${missing[*]}" >&2
  exit 1
fi
