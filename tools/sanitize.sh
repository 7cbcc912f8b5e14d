#!/usr/bin/env bash
# Builds vkvo with sanitizers in a build folder of its own and runs ctest there (docs/testing.md, "Sanitizers").
#   tools/sanitize.sh address [ctest arguments]   AddressSanitizer + UndefinedBehaviorSanitizer + leaks; all tests
#   tools/sanitize.sh thread  [ctest arguments]   ThreadSanitizer; the tests of the VO's threads (see below)
# Any report fails the test that made it. BUILD_DIR overrides the folder (build-asan, build-tsan).
set -euo pipefail
cd "$(dirname "$0")/.."
kind=${1:-}
shift || true
case "$kind" in
  address) flags=address,undefined build=${BUILD_DIR:-build-asan} default_args=() ;;
  # The stream, the pipeline of `vkvo run` and StereoOdometry (with the real SuperPoint where the data is). Not the
  # VoSynth tests: the renderer that makes their sequences runs cv::parallel_for_ on OpenCV's TBB workers, whose
  # hand-offs ThreadSanitizer cannot see (libtbb is not built with it), so it reports every pixel they write.
  thread) flags=thread build=${BUILD_DIR:-build-tsan} default_args=(-R "OdometryStream|StereoOdometry|Pipeline") ;;
  *) echo "usage: tools/sanitize.sh address|thread [ctest arguments]" >&2; exit 2 ;;
esac
if [ $# -eq 0 ] && [ ${#default_args[@]} -gt 0 ]; then set -- "${default_args[@]}"; fi
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVKVO_SANITIZE="$flags" -DVKVO_BUILD_BENCHMARKS=OFF
cmake --build "$build" -j"$(nproc)"
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$PWD/tools/sanitizers/tsan.supp"
ctest --test-dir "$build" --output-on-failure --timeout 1800 "$@"
