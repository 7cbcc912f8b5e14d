#!/usr/bin/env bash
# Packs what a run on another Linux x86-64 machine without Debian's libraries needs (a GPU machine of a CUDA image,
# say) into .devkit/ (git-ignored): the stripped `vkvo`, the data-free GPU test suites (runtime, SuperPoint and
# SuperGlue against their C++ references, where the build has them), the shared libraries these load but glibc's
# and the C++ runtime's, and the SuperPoint pack; tools/device_check.sh runs from there. The golden-data suites
# (superpoint_data, superglue_data) come too: they run on the device where its checkout has the data (shared/).
#
#   tools/device_kit.sh [BUILD_DIR]      (default build/; needs the shared data for the packs)
#
# Debian's OpenCV image codecs pull in GDAL and GDCM (over 150 MB with their own dependencies) for formats vkvo
# never reads; they are replaced by stub libraries that export the symbols the codecs import (each returns 0), so
# the closure is about 50 MB (15 MB compressed). BLAS and LAPACK are the reference ones (Ceres' small dense
# problems do not need OpenBLAS's 42 MB).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
VKVO="$BUILD_DIR/bin/vkvo"
KIT=.devkit
LIBDIR=/usr/lib/x86_64-linux-gnu
[ -x "$VKVO" ] || { echo "device_kit: $VKVO not built" >&2; exit 1; }
DATA=${VKVO_DATA:-../shared}
[ -f "$DATA/models/superpoint_v1.onnx" ] || { echo "device_kit: $DATA/models/superpoint_v1.onnx not found (set VKVO_DATA)" >&2; exit 1; }

rm -rf "$KIT"
mkdir -p "$KIT/stage/lib" "$KIT/stage/bin" "$KIT/stage/models" "$KIT/stubs"
stage=$KIT/stage

# Stubs: every symbol that a library of the closure imports from these, as a function returning 0.
imports=$(for lib in "$LIBDIR"/libopencv_imgcodecs.so.*; do nm -D --undefined-only "$lib"; done | awk '{print $2}' |
          sed 's/@.*//' | sort -u)
for soname in libgdal.so.32 libgdcmMSFF.so.3.0 libgdcmDSED.so.3.0; do
  defined=$(nm -D --defined-only "$(readlink -f "$LIBDIR/$soname")" | awk '{print $3}' | sed 's/@.*//' | sort -u)
  {
    echo ".text"
    comm -12 <(echo "$imports") <(echo "$defined") |
      while read -r symbol; do printf '.globl %s\n.type %s,@function\n%s:\n  xorl %%eax, %%eax\n  ret\n' \
                                      "$symbol" "$symbol" "$symbol"; done
  } > "$KIT/stubs/$soname.s"
  gcc -shared -nostdlib -Wl,-soname,"$soname" -o "$stage/lib/$soname" "$KIT/stubs/$soname.s"
done
cp -L "$LIBDIR/blas/libblas.so.3" "$LIBDIR/lapack/liblapack.so.3" "$stage/lib/"

# The rest of the closure, resolved with the stubs and reference BLAS in front; vkvo loads the Vulkan loader itself.
cp "$VKVO" "$stage/bin/vkvo"
for suite in runtime superpoint superglue superpoint_data superglue_data; do
  [ -x "$BUILD_DIR/tests/vkvo_test_$suite" ] && cp "$BUILD_DIR/tests/vkvo_test_$suite" "$stage/bin/"
done
strip "$stage"/bin/*
cp -L "$LIBDIR/libvulkan.so.1" "$stage/lib/"
# The GLVND libraries that NVIDIA's Vulkan driver (libGLX_nvidia) loads and a CUDA image may lack: on an H200
# machine of one (2026-12-04) vkCreateInstance failed with ErrorIncompatibleDriver without them.
glvnd="libGLdispatch.so.0 libGLX.so.0 libEGL.so.1 libOpenGL.so.0 libGL.so.1 libGLESv2.so.2"
for lib in $glvnd; do
  cp -L "$LIBDIR/$lib" "$stage/lib/" ||
    { echo "device_kit: $LIBDIR/$lib missing (apt-get install libglvnd0 libglx0 libegl1 libopengl0 libgl1 libgles2)" >&2; exit 1; }
done
LD_LIBRARY_PATH="$PWD/$stage/lib" ldd "$stage"/bin/* $(for lib in $glvnd; do echo "$stage/lib/$lib"; done) |
  awk '$3 ~ /^\// {print $1, $3}' | sort -u |
  grep -v -E '^(libc|libm|libpthread|libdl|librt|libstdc\+\+|libgcc_s)\.so' |
  while read -r name path; do
    case "$path" in "$PWD/$stage"/*) ;; *) cp -L "$path" "$stage/lib/$name" ;; esac
  done
if LD_LIBRARY_PATH="$PWD/$stage/lib" ldd "$stage"/bin/* | grep -q "not found"; then
  echo "device_kit: unresolved libraries" >&2; exit 1
fi

# SuperPoint only: the synthetic SuperGlue pack (72 MB of random weights, which do not compress) would not fit what
# the device tool carries (64 MiB).
"$VKVO" convert --onnx "$DATA/models/superpoint_v1.onnx" --out "$stage/models/superpoint_v1.vkvopack" > /dev/null
tar -C "$stage" -cf - . | xz -T0 -6 > "$KIT/kit.tar.xz"
rm -rf "$stage"
echo "device_kit: $KIT/kit.tar.xz ($(du -h "$KIT/kit.tar.xz" | cut -f1)); on the device: tools/device_check.sh"
