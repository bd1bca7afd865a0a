#!/usr/bin/env bash
# Fresh-machine path: install the Debian packages, build, generate the Cornell box and run probebake on it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out
./build/samples/make-scene cornell -o out/cornell.glb
./build/cli/probebake info out/cornell.glb
