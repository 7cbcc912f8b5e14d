#!/usr/bin/env bash
# README command 2: installs the dependencies, builds vkvo and runs every test (GoogleTest under ctest).
# Tests labelled `data` read ../shared (or $VKVO_DATA) and skip with a message where it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" -j"$(nproc)"
# Tests run side by side, one per core (most are short and single-threaded: process start, Vulkan setup, pipeline
# creation); the `data` tests ask for two processors (tests/CMakeLists.txt), so the GPU-heavy ones still get the
# whole of a 2-core machine.
ctest --test-dir "$BUILD_DIR" --output-on-failure --timeout 900 -j"$(nproc)" "$@"
# The parsers of outside input under libFuzzer + ASan/UBSan, each for a bounded time (docs/bad-input.md).
tools/fuzz.sh --ci
