#!/usr/bin/env bash
# Installs every build and test dependency of probebake from Debian 12 (bookworm) packages.
# Safe to run again; needs root (or sudo). Package names only: no downloads from elsewhere.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git clang libclang-rt-14-dev
  # formatting (.clang-format is pinned to this version; scripts/check-format.sh)
  clang-format-14
  # tests and benchmarks
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  # scene input: glTF (tinygltf needs nlohmann-json and stb), Draco, images
  libtinygltf-dev nlohmann-json3-dev libstb-dev libdraco-dev
  # optimised glTF: EXT_meshopt_compression geometry, EXT_texture_webp images
  libmeshoptimizer-dev libwebp-dev
  # CPU rays, signed distance fields (OpenVDB needs Boost headers and TBB), EXR images
  libembree-dev libopenvdb-dev libnanovdb-dev libboost-dev libtbb-dev libopenexr-dev libimath-dev
  # command line and text
  libcli11-dev libfmt-dev libxxhash-dev
  # vector math shared by C++ and the GLSL struct header
  libglm-dev
  # Vulkan compute: headers + loader, lavapipe CPU driver, shader compiler, validation layers
  libvulkan-dev mesa-vulkan-drivers glslang-tools spirv-tools vulkan-validationlayers vulkan-tools
)

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
