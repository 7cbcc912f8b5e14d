#!/usr/bin/env bash
# Unpacks lavapipe from Debian 12's bookworm-backports (Mesa 25) into a local folder, beside the system's Mesa
# 22.3, and writes an env file that points the Vulkan loader at it: to test and time vkvo on the Mesa that
# Debian 13 and current Ubuntu ship, without changing the system. Downloads with apt at the time it runs (not
# a test; nothing in ctest downloads). Needs the system's libLLVM-15 (installed with mesa-vulkan-drivers).
# Usage: tools/mesa-backports.sh [DIR]        (default DIR: ~/.cache/vkvo/mesa-backports)
#        . DIR/env.sh && ctest --test-dir build -LE data
set -euo pipefail

dir=$(realpath -m "${1:-$HOME/.cache/vkvo/mesa-backports}")
rm -rf "$dir/debs" "$dir/root"  # a rerun unpacks what backports has now, not beside an older version
mkdir -p "$dir/apt/lists/partial" "$dir/debs" "$dir/root"
echo "deb http://deb.debian.org/debian bookworm-backports main" > "$dir/apt/sources.list"
# A private package list: the system's apt state is neither read nor changed.
apt_opts=(-o "Dir::Etc::sourcelist=$dir/apt/sources.list" -o "Dir::Etc::sourceparts=-"
          -o "Dir::State::Lists=$dir/apt/lists" -o "Dir::Cache=$dir/apt" -o "APT::Sandbox::User=$(id -un)")
apt-get "${apt_opts[@]}" update -qq
# lavapipe and the libdrm it was built against (newer than bookworm's); its libLLVM-15 is bookworm's own.
(cd "$dir/debs" && apt-get "${apt_opts[@]}" download \
  mesa-vulkan-drivers/bookworm-backports libdrm2/bookworm-backports libdrm-amdgpu1/bookworm-backports)
for deb in "$dir"/debs/*.deb; do dpkg-deb -x "$deb" "$dir/root"; done

libdir="$dir/root/usr/lib/x86_64-linux-gnu"
icd="$dir/root/usr/share/vulkan/icd.d/lvp_icd.json"
[ -f "$libdir/libvulkan_lvp.so" ] && [ -f "$icd" ] || { echo "mesa-backports: no lavapipe in $dir/debs" >&2; exit 1; }
sed -i "s#\"library_path\": *\"[^\"]*\"#\"library_path\": \"$libdir/libvulkan_lvp.so\"#" "$icd"
cat > "$dir/env.sh" <<EOF
# Source this to run vkvo on $(dpkg-deb -f "$dir"/debs/mesa-vulkan-drivers_*.deb Version) lavapipe.
export VK_ICD_FILENAMES=$icd
export LD_LIBRARY_PATH=$libdir\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}
export MESA_SHADER_CACHE_DIR=$dir/shader-cache  # not shared with the system Mesa's cache
EOF
echo "mesa-backports: . $dir/env.sh  (then 'vkvo devices' names the driver)"
