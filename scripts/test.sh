#!/usr/bin/env bash
# Installs what is missing, builds everything with warnings as errors, runs the loader and reader tests
# under AddressSanitizer + UndefinedBehaviorSanitizer, then the whole suite with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)

cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DPROBEBAKE_SANITIZE=address,undefined \
  -DPROBEBAKE_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-asan -j "$jobs" --target probebake scene_tests formats_tests
(cd build-asan/tests/scene && ./scene_tests --gtest_brief=1)
(cd build-asan/tests/formats && ./formats_tests --gtest_brief=1)

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPROBEBAKE_WERROR=ON >/dev/null
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs"
