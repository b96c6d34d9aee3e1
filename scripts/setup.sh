#!/usr/bin/env bash
# Installs the Debian 12 packages hmdlod needs to build, test and run headless — only those missing,
# so a second run changes nothing and takes about a second. Needs root (or sudo) only to install.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git clang libclang-rt-14-dev
  libusb-1.0-0-dev libhidapi-dev libudev-dev umockdev libumockdev-dev
  libglfw3-dev libegl-dev libgl-dev libegl1-mesa-dev libgl1-mesa-dri libepoxy-dev mesa-utils
  libcglm-dev libopenmesh-dev libmeshoptimizer-dev libcjson-dev libpng-dev zlib1g-dev libassimp-dev assimp-utils
  xvfb xauth x11-utils gnuplot-nox hyperfine valgrind glpk-utils parallel libopenhmd-dev
  python3-numpy python3-scipy python3-skimage python3-pil
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
  as_root=()
elif command -v sudo >/dev/null; then
  as_root=(sudo)
else
  echo "setup: missing packages: ${missing[*]}" >&2
  echo "setup: run this script as root (or install sudo) to install them" >&2
  exit 1
fi

echo "setup: installing ${#missing[@]} packages: ${missing[*]}"
# A fresh machine has no package lists yet; refresh them once before installing.
"${as_root[@]}" apt-get update -q
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
