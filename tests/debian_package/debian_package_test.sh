#!/usr/bin/env bash
# The Debian package (`cpack -G DEB`, CMakeLists.txt): it is made, holds the
# executable, its modules, the geometry library with its headers and CMake
# package, and, unpacked into a clean root, renders the showcase from
# another folder.
#   bash tests/debian_package/debian_package_test.sh BUILD_DIR
set -euo pipefail
build=$(realpath "${1:?usage: debian_package_test.sh BUILD_DIR}")
source=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work/out" >/dev/null)
version=$(sed -n 's/^project(isotrace VERSION \([0-9.]*\).*/\1/p' "$source/CMakeLists.txt")
deb="$work/out/isotrace_${version}_amd64.deb"
[ -f "$deb" ] || { echo "debian_package_test: no $deb made" >&2; ls "$work/out" >&2; exit 1; }
contents=$(dpkg-deb -c "$deb")
for expected in ./usr/bin/isotrace ./usr/lib/isotrace/isotrace_openimageio.so ./usr/lib/isotrace/isotrace_assimp.so \
    ./usr/include/isotrace/geometry/tracing/implicit_surface.h \
    ./usr/lib/cmake/isotrace_geometry/isotrace_geometryConfig.cmake; do
  grep -q " $expected\$" <<< "$contents" || { echo "debian_package_test: $expected is not in the package" >&2; exit 1; }
done
grep -q 'libisotrace_geometry' <<< "$contents" || { echo "debian_package_test: no geometry library" >&2; exit 1; }
if grep -q '_kernels\.h$' <<< "$contents"; then echo "debian_package_test: private kernel headers installed" >&2; exit 1; fi
depends=$(dpkg-deb -f "$deb" Depends)
grep -q libembree <<< "$depends" || { echo "debian_package_test: Depends lacks Embree: $depends" >&2; exit 1; }
dpkg -x "$deb" "$work/root"
# The installed headers are the API: each includes only installed headers,
# and none speaks of the private vector layouts.
include_root="$work/root/usr/include/isotrace"
while IFS= read -r header; do
  while IFS= read -r included; do
    [ -f "$include_root/$included" ] || { echo "debian_package_test: ${header#$include_root/} includes $included, which is not installed" >&2; exit 1; }
  done < <(sed -n 's/^#include "\(geometry\/[^"]*\)".*/\1/p' "$header")
done < <(find "$include_root" -name '*.h')
if grep -rlE '\b[Ll]anes?\b|Lane[A-Z]' "$include_root"; then echo "debian_package_test: installed headers above speak of vector lanes" >&2; exit 1; fi
mkdir "$work/elsewhere"
cd "$work/elsewhere"
"$work/root/usr/bin/isotrace" render "$source/scenes/showcase.json" --width 64 --height 48 --spp 4 --quiet -o showcase.exr
[ -s showcase.exr ] && [ -s showcase.png ] || { echo "debian_package_test: no render" >&2; exit 1; }
echo "debian_package_test: $(basename "$deb"), $(du -k "$deb" | cut -f1) KB, $(grep -c '' <<< "$contents") entries; renders from $work/elsewhere"
