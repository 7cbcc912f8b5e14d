#!/usr/bin/env bash
# README command 1: installs the dependencies, builds vkvo and runs the main job on the default sample.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" -j"$(nproc)"
VKVO="$BUILD_DIR/bin/vkvo"
"$VKVO" devices
"$VKVO" bench --repeat 5
