#!/usr/bin/env bash
# The day cycle's error at each hour against a fresh bake of that hour (issue #43; docs/results/runtime.md "Sky and
# time of day"). Bakes the courtyard's 12^3 grid (or DAY_SCENE's DAY_GRID^3) at 35,120, runs it through a day with
# `probebake run --day-cycle` scored against the path-traced reference of each hour from 7:00 to 17:00, then bakes
# each hour afresh and scores that bake's first frame against the same reference (the same receivers and paths).
# Prints one table row per hour.
#
#   scripts/day_cycle_error.sh [BUILD_DIR] [DAY_SECONDS] [HYSTERESIS] [RELIGHT_FRAMES]   (defaults: build 60 0.5 4)
#   DAY_SCENE="rooms --count 4 --detail 8 --windows" DAY_GRID=16 scripts/day_cycle_error.sh ...   (another scene)
set -euo pipefail
build=${1:-build} day=${2:-60} hysteresis=${3:-0.5} relight=${4:-4}
scene=${DAY_SCENE:-courtyard} grid=${DAY_GRID:-12}
probebake=$build/cli/probebake
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/samples/make-scene" $scene -o "$work/yard.glb" >/dev/null
"$probebake" "$work/yard.glb" --sky physical --sun 35,120 --placement grid --grid "$grid" -o "$work/day.probes" >/dev/null
reference="--receivers 512 --paths 1024"
per_hour=$((day * 60 / 24)) # frames of an hour at 60 frames a second
# The sun of hour h as probebake run --day-cycle moves it (run_lighting_changes.cpp): from east (+X) at 6:00 over
# 60 degrees towards +Z at noon, as --sun ELEVATION,AZIMUTH.
sun_of() {
  awk -v h="$1" 'BEGIN { pi = atan2(0, -1); a = pi * (h - 6) / 12; r = pi / 3
    x = cos(a); y = sin(a) * sin(r); z = sin(a) * cos(r); n = sqrt(x * x + y * y + z * z); x /= n; y /= n; z /= n
    printf "%.6f,%.6f", atan2(y, sqrt(1 - y * y)) * 180 / pi, atan2(x, -z) * 180 / pi }'
}
hours="7 8 9 10 11 12 13 14 15 16 17"
frames=$(for h in $hours; do echo $((per_hour * (h - 6))); done | paste -sd,)
rmse() { sed -nE 's/.*indirect relative RMSE ([0-9.]+).*/\1/p'; }
"$probebake" run "$work/day.probes" --scene "$work/yard.glb" --sky physical --sun 35,120 --day-cycle "$day" \
  --hysteresis "$hysteresis" --relight-frames "$relight" --frames $((per_hour * 11 + 1)) --reference "$work/day" \
  --at-frames "$frames" $reference | rmse >"$work/day.txt"
echo "| hour | day cycle | fresh bake | ratio |"
echo "|---|--:|--:|--:|"
row=1
for h in $hours; do
  sun=$(sun_of "$h")
  "$probebake" "$work/yard.glb" --sky physical --sun "$sun" --placement grid --grid "$grid" -o "$work/h$h.probes" >/dev/null
  fresh=$("$probebake" run "$work/h$h.probes" --scene "$work/yard.glb" --sky physical --sun "$sun" --frames 1 \
    --reference "$work/h$h" --at-frames 0 $reference | rmse)
  cycle=$(sed -n "${row}p" "$work/day.txt")
  awk -v h="$h" -v c="$cycle" -v f="$fresh" 'BEGIN { printf "| %d:00 | %.4f | %.4f | %.2f |\n", h, c, f, c / f }'
  row=$((row + 1))
done
