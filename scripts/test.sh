#!/usr/bin/env bash
# Installs what is missing, builds everything with warnings as errors, runs the loader and reader tests
# under AddressSanitizer + UndefinedBehaviorSanitizer, then the whole suite with CTest, then each libFuzzer
# target for a bounded time (scripts/fuzz.sh; PROBEBAKE_FUZZ_SECONDS per target, 0 skips the stage).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/check-format.sh
jobs=$(nproc)

cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DPROBEBAKE_SANITIZE=address,undefined \
  -DPROBEBAKE_BUILD_BENCHMARKS=OFF >/dev/null
asan_tests="scene_tests formats_file_test formats_corruption_test formats_validate_test formats_octree_test formats_trace_mesh_test
  scene_fuzz_regression_test formats_fuzz_regression_test"
cmake --build build-asan -j "$jobs" --target probebake $asan_tests
for t in $asan_tests; do
  dir=$(dirname "$(find build-asan/tests -name "$t" -type f | head -n 1)")
  echo "== $t (address + undefined behaviour sanitizers)"
  (cd "$dir" && "./$t" --gtest_brief=1)
done

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPROBEBAKE_WERROR=ON >/dev/null
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs"

# Fuzzing: clang build of the fuzz targets only, then each fuzzer on a copy of its seeds (build-fuzz).
fuzz_seconds=${PROBEBAKE_FUZZ_SECONDS:-60}
if [ "$fuzz_seconds" != 0 ]; then
  bash scripts/fuzz.sh --time "$fuzz_seconds"
fi
