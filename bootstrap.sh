#!/usr/bin/env bash
# Installs the Debian 12 packages glintlab needs. Idempotent; run as root or with sudo.
set -euo pipefail
PKGS=(
  build-essential cmake pkg-config
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-dev glslang-tools spirv-tools
  libglm-dev
  libopenimageio-dev openimageio-tools libopenexr-dev libdeflate-dev  # EXR sequences' fast path (experiments/sources/)
  libpng-dev  # sRGB PNGs read without OpenImageIO (experiments/sources/png_file.h)
  libopencolorio-dev opencolorio-tools
  libgtest-dev
  nlohmann-json3-dev libcli11-dev libxxhash-dev libopencv-video-dev ninja-build
  fonts-dejavu-core
  clang libclang-rt-14-dev llvm
  python3 python3-numpy python3-scipy python3-matplotlib python3-pil python3-jinja2 chromium  # report (experiments/report/) and its browser test
  python3-optuna python3-sklearn parallel slurm-wlm munge  # tune (experiments/tune/): Optuna, its importances, schedulers
  pybind11-dev python3-dev python3-pybind11 python3-pytest  # `import glintlab` (experiments/python/) and its tests
  strace  # the install test: the installed glintlab opens nothing in the source or build tree (tests/install/)
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "bootstrap: all ${#PKGS[@]} packages already installed"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "bootstrap: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
