#!/usr/bin/env bash
# Installs every Debian 12 package vkvo needs to build, test and run (idempotent, non-interactive).
# Usage: tools/setup.sh        (as root, or with sudo available)
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # Vulkan: loader + headers (Vulkan-Hpp), lavapipe CPU driver, validation layers, tools
  libvulkan-dev vulkan-tools mesa-vulkan-drivers vulkan-validationlayers
  # shader toolchain
  glslc glslang-tools spirv-tools
  # maths, vision, optimisation, threads
  libeigen3-dev libopencv-dev libopencv-contrib-dev libceres-dev libtbb-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # CLI, logging, config, json
  libcli11-dev libspdlog-dev libfmt-dev libyaml-cpp-dev nlohmann-json3-dev
  # ONNX reading (converter)
  libonnx-dev libprotobuf-dev protobuf-compiler
  # the Python module (pybind11, for Debian's python3 and numpy) and its pytest suites
  pybind11-dev python3-dev python3-numpy python3-pytest
  # the C++ style check (tools/format.sh)
  clang-format
  # the libFuzzer targets (tools/fuzz.sh): clang with its fuzzer and sanitizer runtimes
  clang-14 libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
