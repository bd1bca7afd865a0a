#!/usr/bin/env bash
# Fresh-machine path: install the Debian packages, build, generate the Cornell box, describe it, bake it,
# validate the file and load it into the Vulkan runtime (lavapipe when there is no GPU).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out
./build/samples/make-scene cornell -o out/cornell.glb
./build/cli/probebake info out/cornell.glb
./build/cli/probebake out/cornell.glb --max-depth 3
./build/cli/probebake validate out/cornell.probes
./build/cli/probebake run out/cornell.probes --frames 100
