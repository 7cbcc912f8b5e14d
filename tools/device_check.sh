#!/usr/bin/env bash
# The GPU checks, run on a machine that has the kit of tools/device_kit.sh (.devkit/kit.tar.xz) but not Debian's
# libraries: the devices vkvo sees, the data-free GPU test suites the kit carries (runtime, SuperPoint, SuperGlue:
# every kernel form against its C++ reference, in every precision the GPU has), `vkvo bench` of SuperPoint in every
# precision, and `vkvo run` on a rendered 752x480 sequence (issue 7's frames/s; NN matcher, since only synthetic
# SuperGlue weights exist here). Each step's log goes to $OUT (default out/device; seven files: gpu, devices,
# tests, bench_superpoint, synth and run logs and the run's summary.json), and a failing step does not stop the
# others.
# Issue 39 (tensor cores, one submission per call; docs/tensor-cores.md) adds, where the checkout has the data in
# $VKVO_DATA (default shared/): the golden suites at fp16s with the tensor-core kernels (SuperPoint: >= 95 % of
# keypoints within 1 px, descriptor cosine >= 0.995; SuperGlue: >= 97 % identical matches), and the issue's targets
# with and without them (VKVO_COOPERATIVE_MATRIX=0): SuperPoint 752x480 and SuperGlue N = 1000 per call, `vkvo run`
# frames/s on EuRoC (NN matcher and SuperGlue) and KITTI. Each of those logs is named *_coopmat_on / _off.
#
#   [OUT=DIR] [REPEAT=N] [VKVO_DATA=DIR] tools/device_check.sh [FRAMES]
#       (defaults: out/device, 20 timed calls, shared/, 200 frames)
set -uo pipefail
cd "$(dirname "$0")/.."
FRAMES=${1:-200}
OUT=${OUT:-out/device}
# The unpacked kit, the rendered sequence and the run's outputs, which need not come back: a fresh temporary
# folder ($TMPDIR or the system's), removed on exit.
SCRATCH=$(mktemp -d -t vkvo-check.XXXXXX) || { echo "device_check: cannot make a temporary folder"; exit 1; }
trap 'rm -rf "$SCRATCH"' EXIT
KIT=$SCRATCH/kit
WORK=$SCRATCH/work
mkdir -p "$OUT" "$KIT" "$WORK"
[ -f .devkit/kit.tar.xz ] || { echo "device_check: no .devkit/kit.tar.xz (tools/device_kit.sh)"; exit 1; }
# Python's lzma where tar has no xz to call.
tar -C "$KIT" -xJf .devkit/kit.tar.xz 2> /dev/null ||
  python3 -c "import sys, tarfile; tarfile.open(sys.argv[1]).extractall(sys.argv[2])" .devkit/kit.tar.xz "$KIT" ||
  { echo "device_check: cannot unpack .devkit/kit.tar.xz"; exit 1; }
export LD_LIBRARY_PATH="$KIT/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
for icd in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json \
           /etc/vulkan/icd.d/nvidia_icd.json; do
  if [ -f "$icd" ]; then export VK_DRIVER_FILES="$icd" VK_ICD_FILENAMES="$icd"; break; fi
done
VKVO="$KIT/bin/vkvo"
step() {  # name, command...
  local name=$1; shift
  echo "== $name: $*"
  local start=$SECONDS
  "$@" > "$OUT/$name.txt" 2>&1
  local rc=$?
  tail -n 25 "$OUT/$name.txt"
  echo "== $name: rc=$rc, $((SECONDS - start)) s"
}

nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv > "$OUT/gpu.txt" 2>&1 && cat "$OUT/gpu.txt"
step devices "$VKVO" devices
run_suites() {  # every test suite in the kit, one after the other; fails if any fails
  local rc=0
  for suite in "$KIT"/bin/vkvo_test_*; do
    [ -x "$suite" ] || continue
    echo "== $(basename "$suite")"
    "$suite" --gtest_brief=1 || rc=1
  done
  return $rc
}
step tests run_suites
step bench_superpoint "$VKVO" bench --superpoint --model "$KIT/models/superpoint_v1.vkvopack" --repeat "${REPEAT:-20}"
step synth "$VKVO" synth --out "$WORK/sequence" --preset default --frames "$FRAMES"
step run "$VKVO" run --config config/euroc.yaml --dataset "$WORK/sequence" --model "$KIT/models/superpoint_v1.vkvopack" \
     --matcher nn --out "$WORK/run"
[ -f "$WORK/run/summary.json" ] && cp "$WORK/run/summary.json" "$OUT/run_summary.json"

# Issue 39: the tensor-core path's accuracy and the targets, with it and without.
DATA=$(cd "${VKVO_DATA:-shared}" 2> /dev/null && pwd) || DATA=
export VKVO_DATA=$DATA
if [ -n "$DATA" ] && [ -f "$DATA/models/superpoint_v1.onnx" ] && [ -d "$DATA/golden/superpoint" ]; then
  step golden_superpoint_coopmat_on "$KIT/bin/vkvo_test_superpoint_data" --gtest_filter='Golden/*fp16s*'
else
  echo "== golden_superpoint: skipped, no \$VKVO_DATA/models/superpoint_v1.onnx and golden/superpoint"
fi
SUPERGLUE=
if [ -n "$DATA" ] && [ -f "$DATA/models/superglue_synthetic.onnx" ]; then
  SUPERGLUE=$WORK/superglue_synthetic.vkvopack
  "$VKVO" convert --onnx "$DATA/models/superglue_synthetic.onnx" --out "$SUPERGLUE" > /dev/null || SUPERGLUE=
  [ -d "$DATA/golden/superglue_synthetic" ] &&
    step golden_superglue_coopmat_on "$KIT/bin/vkvo_test_superglue_data" --gtest_filter='*fp16s*'
else
  echo "== SuperGlue: skipped, no \$VKVO_DATA/models/superglue_synthetic.onnx"
fi
EUROC=$DATA/datasets/euroc_mh01_subset
KITTI=$DATA/datasets/kitti_seq01_f000-050
for coopmat in 1 0; do
  tag=coopmat_$([ $coopmat = 1 ] && echo on || echo off)
  export VKVO_COOPERATIVE_MATRIX=$coopmat
  step "bench_kernels_$tag" "$VKVO" bench --kernels --precision fp16s --repeat "${REPEAT:-20}"
  step "bench_superpoint_$tag" "$VKVO" bench --superpoint --model "$KIT/models/superpoint_v1.vkvopack" \
       --precision fp16s --repeat "${REPEAT:-20}"
  [ -n "$SUPERGLUE" ] && step "bench_superglue_$tag" "$VKVO" bench --superglue --model "$SUPERGLUE" \
       --precision fp16s --keypoints 1000 --repeat "${REPEAT:-20}"
  if [ -n "$DATA" ] && [ -d "$EUROC" ]; then
    step "run_euroc_nn_$tag" "$VKVO" run --config config/euroc.yaml --dataset "$EUROC" \
         --model "$KIT/models/superpoint_v1.vkvopack" --matcher nn --out "$WORK/euroc_nn_$tag"
    [ -n "$SUPERGLUE" ] && step "run_euroc_superglue_$tag" "$VKVO" run --config config/euroc.yaml --dataset "$EUROC" \
         --model "$KIT/models/superpoint_v1.vkvopack" --matcher superglue --superglue "$SUPERGLUE" \
         --out "$WORK/euroc_superglue_$tag"
  fi
  [ -n "$DATA" ] && [ -d "$KITTI" ] && step "run_kitti_$tag" "$VKVO" run --config config/kitti.yaml \
       --dataset "$KITTI" --model "$KIT/models/superpoint_v1.vkvopack" --matcher nn --out "$WORK/kitti_$tag"
done
unset VKVO_COOPERATIVE_MATRIX
