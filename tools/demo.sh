#!/usr/bin/env bash
# README command 1: installs the dependencies, builds vkvo and runs the main job on the default sample:
# a synthetic 200-frame stereo sequence with the lights switched off and on again, the VO on it, and the
# evaluation against its ground truth (ATE, timing table, trajectory plot).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-out/demo}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" -j"$(nproc)"
VKVO="$BUILD_DIR/bin/vkvo"

"$VKVO" devices
"$VKVO" synth --out "$OUT/sequence" --preset default
# The SuperPoint weights: --model, $VKVO_MODELS, then ../shared/models (converted on first use); vkvo explains
# how to obtain them when none is found.
"$VKVO" run --config config/euroc.yaml --dataset "$OUT/sequence" --out "$OUT/run" ${VKVO_MODEL:+--model "$VKVO_MODEL"}
"$VKVO" eval --estimate "$OUT/run/trajectory.txt" --groundtruth "$OUT/sequence/groundtruth_tum.txt" \
             --plot "$OUT/run/trajectory.png" --json "$OUT/run/eval.json"
echo "trajectory: $OUT/run/trajectory.txt   plot: $OUT/run/trajectory.png   summary: $OUT/run/summary.json"
