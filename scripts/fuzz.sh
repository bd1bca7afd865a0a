#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan), assembles each one's seed corpus in the build
# folder and runs each fuzzer for a bounded time. Fails when a fuzzer reports a crash, timeout, leak or
# memory-limit breach, and prints the reproducer; copy it to tests/data/fuzz-regressions/<target>/.
#
#   bash scripts/fuzz.sh [--time SECONDS] [TARGET...]     TARGET: scene_loader probes_reader validator camera_path
#                                                         sky_environment
#
# Environment: PROBEBAKE_FUZZ_BUILD (build folder, default build-fuzz), PROBEBAKE_FUZZ_SECONDS (per target,
# default 60; --time wins). The corpus in <build>/fuzz-corpus/<target> grows from run to run.
set -euo pipefail
cd "$(dirname "$0")/.."
src=$(pwd)
build=${PROBEBAKE_FUZZ_BUILD:-build-fuzz}
seconds=${PROBEBAKE_FUZZ_SECONDS:-60}
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --time) seconds=$2; shift 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(scene_loader probes_reader validator camera_path sky_environment)

# Only the fuzz targets and the libraries they link: no runtime, no benchmarks, no test executables.
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DPROBEBAKE_BUILD_FUZZERS=ON -DPROBEBAKE_BUILD_RUNTIME=OFF \
  -DPROBEBAKE_BUILD_BENCHMARKS=OFF -DPROBEBAKE_WERROR=ON >/dev/null
cmake --build "$build" -j "$(nproc)" --target $(printf 'fuzz_%s ' "${targets[@]}")
build=$(cd "$build" && pwd)

# Seeds: committed cases and regressions, golden files, generated scenes, ../shared/scenes when present.
seed() { # seed TARGET FILE...: copies the files that exist into the target's corpus
  local dir="$build/fuzz-corpus/$1"; shift
  mkdir -p "$dir"
  for f in "$@"; do [ -f "$f" ] && cp -f "$f" "$dir/" || true; done
}
make_scene=$(ls "$src"/build*/samples/make-scene 2>/dev/null | head -n 1 || true)
generated="$build/fuzz-generated"
mkdir -p "$generated"
if [ -n "$make_scene" ]; then
  for kind in cornell triangle empty furnace leak plane-light; do
    "$make_scene" "$kind" -q -o "$generated/$kind.glb" || echo "make-scene $kind failed (seed skipped)"
  done
fi
seed scene_loader "$src"/tests/data/fuzz/scene_loader/* "$src"/tests/data/fuzz-regressions/scene_loader/* \
  "$src"/tests/data/gltf-lenient/*.gl* "$generated"/*.glb "$src"/../shared/scenes/*/*.glb "$src"/../shared/scenes/*/*.gltf
for t in probes_reader validator; do
  seed $t "$src"/tests/data/golden/*.probes "$src"/tests/data/fuzz/$t/* "$src"/tests/data/fuzz-regressions/$t/*
done
seed camera_path "$src"/tests/data/fuzz/camera_path/* "$src"/tests/data/fuzz-regressions/camera_path/*
seed sky_environment "$src"/tests/data/fuzz/sky_environment/* "$src"/tests/data/fuzz-regressions/sky_environment/*

failed=()
for t in "${targets[@]}"; do
  exe=$(find "$build/tests" -name "fuzz_$t" -type f | head -n 1)
  artifacts="$build/fuzz-artifacts/$t/"
  scratch="$build/fuzz-scratch/$t"
  mkdir -p "$artifacts" "$scratch"
  dict=(-dict="$src/tests/formats/fuzz_probes_reader.dict")
  [ "$t" = scene_loader ] && dict=(-dict="$src/tests/scene/fuzz_scene_loader.dict")
  [ "$t" = camera_path ] && dict=()
  [ "$t" = sky_environment ] && dict=()
  echo "== fuzz_$t for ${seconds}s (corpus $build/fuzz-corpus/$t)"
  # The loader resolves external URIs against $scratch/scene only (fuzz_scene_loader_entry.cpp).
  if ! (cd "$scratch" && PROBEBAKE_FUZZ_SCRATCH="$scratch" UBSAN_OPTIONS=print_stacktrace=1 \
        "$exe" "${dict[@]}" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
        -artifact_prefix="$artifacts" "$build/fuzz-corpus/$t" >"$build/fuzz-$t.log" 2>&1); then
    tail -n 60 "$build/fuzz-$t.log"
    for f in "$artifacts"*; do
      [ -f "$f" ] && echo "fuzz_$t: reproducer $f (copy it to tests/data/fuzz-regressions/$t/)"
    done
    failed+=("$t")
  else
    grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb)|Done [0-9]+ runs" "$build/fuzz-$t.log" || true
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzzing failed: ${failed[*]} (logs: $build/fuzz-<target>.log)"
  exit 1
fi
