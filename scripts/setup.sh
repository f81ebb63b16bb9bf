#!/usr/bin/env bash
# Installs wavepath's build and test dependencies from Debian packages, and what the plot
# scripts in scripts/ import (python3-matplotlib, python3-numpy). The viewer (`wavepath
# view`, docs/viewer.md): GLFW 3 and OpenGL to build it, Xvfb and Mesa's software OpenGL
# (libgl1-mesa-dri) for its test. Distributed rendering (`mpirun -np N wavepath render`,
# docs/distributed.md) and its tests: Open MPI (libopenmpi-dev, openmpi-bin).
# Idempotent: installs only what is missing. Works as root or through sudo.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
  libglm-dev libopenimageio-dev catch2 libtinyobjloader-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libembree-dev oclgrind
  libassimp-dev libpugixml-dev libtinygltf-dev clang libclang-rt-14-dev
  python3-matplotlib python3-numpy
  libglfw3-dev libgl-dev xvfb xauth libgl1-mesa-dri
  libopenmpi-dev openmpi-bin
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  sudo_cmd=()
elif command -v sudo >/dev/null 2>&1; then
  sudo_cmd=(sudo)
else
  echo "setup: missing packages (${missing[*]}) and not root, and sudo is not available" >&2
  exit 1
fi

echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
