#!/usr/bin/env bash
# README command 1: installs the dependencies, builds vkvo and runs the main job on the default sample:
# a synthetic 752x480 stereo sequence with the lights switched off and on again in the middle, the VO on it, and
# the evaluation against its ground truth (ATE, timing table, trajectory plot).
# DEMO_FRAMES (default 60: short enough on lavapipe, where SuperPoint is the slow part, docs/performance.md; use
# 200 on a GPU for the full 10 s preset).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-out/demo}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release
# The CLI alone (the libraries and shaders it links), not the test suites and benchmarks tools/test.sh builds:
# a fresh machine's first demo is mostly this build (docs/demo.md). The build folder stays shared with
# tools/test.sh, whose build then adds the rest.
cmake --build "$BUILD_DIR" -j"$(nproc)" --target vkvo_cli
VKVO="$BUILD_DIR/bin/vkvo"

"$VKVO" devices
FRAMES=${DEMO_FRAMES:-60}
"$VKVO" synth --out "$OUT/sequence" --preset default --frames "$FRAMES" --no-default-events \
              --events "lights_off:$((FRAMES / 2 - 3))-$((FRAMES / 2 + 2))"
# The SuperPoint weights: --model, $VKVO_MODELS, models/, then ../shared/models (converted on first use); vkvo
# explains how to obtain them when none is found.
"$VKVO" run --config config/euroc.yaml --dataset "$OUT/sequence" --out "$OUT/run" ${VKVO_MODEL:+--model "$VKVO_MODEL"}
"$VKVO" eval --estimate "$OUT/run/trajectory.txt" --groundtruth "$OUT/sequence/groundtruth_tum.txt" \
             --plot "$OUT/run/trajectory.png" --json "$OUT/run/eval.json"
echo "trajectory: $OUT/run/trajectory.txt   plot: $OUT/run/trajectory.png   summary: $OUT/run/summary.json"
