#!/usr/bin/env bash
# glintlab as a user without the source tree gets it: the Debian package that `cpack -G DEB` builds
# (its name, its dependencies, its files) and the copy `cmake --install` puts in a prefix, each run
# from a folder outside the source and build trees with the data variables unset. The package's
# program runs `run regression`, `check` against the committed baseline, and `measure` on
# tests/data/blender (default output folder) with `check` against the build tree's own measure;
# every input is copied out first, and where strace works, a path opened or looked at under the
# source or build tree fails the test. The prefix's program prints its data folder and lists the
# experiments. A program beside no data, or GLINTLAB_DATA_DIR naming an empty folder, fails with
# exit 4 and says where it looked and which variable to set. The Python module of the package and of
# the prefix imports (Debian's python3, the package's dist-packages on PYTHONPATH), finds its data
# beside it and compares two images.
#
#   tests/install/install_test.sh SOURCE_DIR BUILD_DIR      (ctest runs it as install.package)
set -euo pipefail

[ $# -eq 2 ] || { echo "usage: $0 SOURCE_DIR BUILD_DIR" >&2; exit 2; }
src=$(cd "$1" && pwd -P)
build=$(cd "$2" && pwd -P)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/glintlab-install-test.XXXXXX")
tmp=$(cd "$tmp" && pwd -P)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "install test: FAIL: $*" >&2; exit 1; }
step() { echo "install test: $*"; }
case "$tmp/" in "$src/"* | "$build/"*) fail "the temporary folder $tmp is inside the source or build tree (set TMPDIR)" ;; esac

# ---------------------------------------------------------------- the package
step "cpack -G DEB"
(cd "$tmp" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/pkg") > "$tmp/cpack.log" 2>&1 ||
  { cat "$tmp/cpack.log"; fail "cpack -G DEB failed"; }
version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
deb=$tmp/pkg/glintlab_${version}_amd64.deb
[ -f "$deb" ] || fail "cpack wrote $(cd "$tmp/pkg" && ls ./*.deb 2>/dev/null), not glintlab_${version}_amd64.deb"

info=$(dpkg-deb -I "$deb")
grep -qx " Package: glintlab" <<<"$info" || fail "dpkg-deb -I: no 'Package: glintlab'"$'\n'"$info"
grep -qx " Version: $version" <<<"$info" || fail "dpkg-deb -I: no 'Version: $version'"$'\n'"$info"
grep -qx " Architecture: amd64" <<<"$info" || fail "dpkg-deb -I: no 'Architecture: amd64'"
depends=$(sed -n 's/^ Depends: //p' <<<"$info" | tr ',' '\n' | sed 's/^ *//; s/ .*//')
[ -n "$depends" ] || fail "dpkg-deb -I: no Depends"
recommends=$(sed -n 's/^ Recommends: //p' <<<"$info" | tr ',' '\n' | sed 's/^ *//; s/ .*//')
[ -n "$recommends" ] || fail "dpkg-deb -I: no Recommends"
bad=$(grep -E -- '-dev$|^(gcc|g\+\+|clang|cpp|cmake|build-essential|libstdc\+\+-[0-9]+-dev)' <<<"$depends"$'\n'"$recommends" || true)
[ -z "$bad" ] || fail "Depends or Recommends names build-time packages: $bad"
# Every library the program, its Python module, libglintlab_ocio.so (which every colour conversion
# loads) and libglintlab_glslang.so (which every render loads) name (ELF NEEDED) belongs to a package it depends on, where dpkg knows it; those of the two
# libraries some commands load (core/util/plugin.h: OpenImageIO, OpenCV) to one it depends on or
# recommends.
if command -v dpkg >/dev/null && command -v ldd >/dev/null && command -v readelf >/dev/null; then
  for elf in "$build/glintlab" "$build"/python/glintlab/_core*.so "$build/libglintlab_oiio.so" \
    "$build/libglintlab_flow.so" "$build/libglintlab_ocio.so" "$build/libglintlab_glslang.so"; do
    case $elf in
      */libglintlab_oiio.so | */libglintlab_flow.so) allowed=$depends$'\n'$recommends; list="Depends or Recommends" ;;
      *) allowed=$depends; list="Depends" ;;
    esac
    needed=$(readelf -d "$elf" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
    [ -n "$needed" ] || fail "readelf -d lists no NEEDED library of $elf"
    libs=$(ldd "$elf")
    declare -A so_of real_of
    for lib in $needed; do
      # The dynamic loader itself (libc6; needed for __tls_get_addr by the position-independent code),
      # which ldd lists by its path, without "=>".
      case $lib in ld-linux*.so.*) continue ;; esac
      so_of[$lib]=$(awk -v l="$lib" '$1 == l && $2 == "=>" {print $3}' <<<"$libs")
      [ -n "${so_of[$lib]}" ] || fail "ldd does not resolve $lib, which $elf needs"
      real_of[$lib]=$(readlink -f "${so_of[$lib]}")
    done
    # One query for all ("package[:arch]: path" a line); the link's path or the file's is registered.
    owners=$(dpkg -S "${so_of[@]}" "${real_of[@]}" 2>/dev/null || true)
    for lib in $needed; do
      [ -n "${so_of[$lib]:-}" ] || continue
      pkg=$(grep -F -e ": ${so_of[$lib]}" -e ": ${real_of[$lib]}" <<<"$owners" | head -n1 | sed 's/[:,].*//' || true)
      [ -n "$pkg" ] || continue
      grep -qx "$pkg" <<<"$allowed" || fail "$elf needs $lib, of the package $pkg, not in $list"
    done
    unset so_of real_of
  done
fi
grep -qx libvulkan1 <<<"$depends" || fail "Depends lacks libvulkan1"
for p in mesa-vulkan-drivers libopenimageio2.4 python3 python3-matplotlib python3-numpy python3-pil python3-optuna; do
  grep -qx "$p" <<<"$recommends" || fail "Recommends lacks $p (the renderer's driver, OpenImageIO, the report's or tune's Python)"
done

files=$(dpkg-deb -c "$deb" | awk '{print $NF}')
for f in ./usr/bin/glintlab ./usr/share/glintlab/shaders/passes/surface.vert ./usr/share/glintlab/shaders/tests/stress_math.comp \
  ./usr/share/glintlab/experiments/data/regression.json ./usr/share/glintlab/experiments/data/paths/orbit-close.json \
  ./usr/share/glintlab/experiments/data/thesis/fig6-7-hdri-match.json \
  ./usr/share/glintlab/experiments/report/glintlab_report.py ./usr/share/glintlab/experiments/tune/glintlab_tune.py \
  ./usr/share/glintlab/metrics/color/ocio/config.ocio ./usr/lib/python3/dist-packages/glintlab/__init__.py \
  ./usr/lib/glintlab/libglintlab_oiio.so ./usr/lib/glintlab/libglintlab_flow.so ./usr/lib/glintlab/libglintlab_ocio.so \
  ./usr/lib/glintlab/libglintlab_glslang.so; do
  grep -qx "$f" <<<"$files" || fail "the package lacks $f"
done
grep -Eqx '\./usr/lib/python3/dist-packages/glintlab/_core\.cpython-[0-9]+-[a-z0-9_]+-linux-gnu\.so' <<<"$files" ||
  fail "the package lacks the Python module usr/lib/python3/dist-packages/glintlab/_core.cpython-*.so"
stray=$(grep -E '\.(cpp|h|o|a|md)$|CMake|/tests/data/' <<<"$files" || true)
[ -z "$stray" ] || fail "the package holds build or source files: $stray"
dpkg-deb -x "$deb" "$tmp/root"

# ---------------------------------------------------------------- cmake --install
step "cmake --install --prefix $tmp/prefix"
cmake --install "$build" --prefix "$tmp/prefix" > "$tmp/install.log" 2>&1 ||
  { cat "$tmp/install.log"; fail "cmake --install failed"; }
[ -x "$tmp/prefix/bin/glintlab" ] || fail "cmake --install put no bin/glintlab in the prefix"

# ---------------------------------------------------------------- running them away from the trees
mkdir -p "$tmp/work" "$tmp/inputs"
cp -r "$src/tests/data/blender" "$tmp/inputs/blender"
cp "$src/results/baselines/regression.json" "$tmp/inputs/regression-baseline.json"
cd "$tmp/work"
# What a user's shell has: no data variables, no OCIO, fresh caches.
clean=(env -u GLINTLAB_DATA_DIR -u GLINTLAB_RESULTS_DIR -u GLINTLAB_REPORT_SCRIPT -u OCIO -u GLINTLAB_VALIDATION
  XDG_CACHE_HOME="$tmp/cache")
tracer=()
if command -v strace >/dev/null && strace -f -qq -o /dev/null true 2>/dev/null; then
  tracer=(strace -f -qq -e trace=%file -o "$tmp/trace")
else
  step "strace is unavailable: the paths the programs open are not checked"
fi
# Runs a program with the clean environment (traced where strace works); its output goes to $tmp/out.
run() {
  local rc=0
  "${clean[@]}" ${tracer[@]+"${tracer[@]}"} "$@" > "$tmp/out" 2>&1 || rc=$?
  if [ ${#tracer[@]} -gt 0 ]; then
    local touched
    touched=$(grep -F -e "\"$src/" -e "\"$build/" -e "\"$src\"" -e "\"$build\"" "$tmp/trace" | head -5 || true)
    [ -z "$touched" ] || fail "$* looked in the source or build tree:"$'\n'"$touched"
  fi
  return $rc
}

pkg=$tmp/root/usr/bin/glintlab
step "--version"
run "$pkg" --version || { cat "$tmp/out"; fail "glintlab --version failed"; }
head -n1 "$tmp/out" | grep -Eqx "glintlab $version \(commit ([0-9a-f]{4,40}(-dirty)?|unknown)\)" ||
  fail "glintlab --version's first line is not 'glintlab $version (commit HASH)': $(head -n1 "$tmp/out")"
grep -qxF "data: $tmp/root/usr/share/glintlab (../share/glintlab beside the executable $pkg)" "$tmp/out" ||
  fail "the package's glintlab does not read its data beside it:"$'\n'"$(cat "$tmp/out")"
[ "$(head -n1 "$tmp/out")" = "$("$build/glintlab" --version | head -n1)" ] ||
  fail "the package's version line differs from the build tree's"

step "run regression"
t0=$(date +%s%N)
run "$pkg" run regression --out "$tmp/work/regression" --no-report ||
  { tail -n 30 "$tmp/out"; fail "glintlab run regression failed"; }
[ -s "$tmp/work/regression/summary.json" ] || fail "run regression wrote no summary.json"
run "$pkg" check "$tmp/work/regression/summary.json" "$tmp/inputs/regression-baseline.json" ||
  { cat "$tmp/out"; fail "glintlab check of the regression run against the committed baseline failed"; }
grep -q "no regression" "$tmp/out" || fail "check said:"$'\n'"$(cat "$tmp/out")"

step "measure (tests/data/blender)"
D=$tmp/inputs/blender
measure_args=(measure --reference "$D/ref/frame_####.exr:ViewLayer.Combined"
  --test spp1="$D/spp1/frame_####.exr:ViewLayer.Combined" --motion-from reference --motion-convention blender --no-report)
run "$pkg" "${measure_args[@]}" || { tail -n 30 "$tmp/out"; fail "glintlab measure failed"; }
[ -s "$tmp/work/results/measure/summary.json" ] ||
  fail "measure without --out wrote no results/measure/summary.json in the current folder"
# The same measure by the build tree's program is the baseline: the package's must not differ.
"${clean[@]}" "$build/glintlab" "${measure_args[@]}" --out "$tmp/build-measure" > "$tmp/out" 2>&1 ||
  { tail -n 30 "$tmp/out"; fail "the build tree's glintlab measure failed"; }
run "$pkg" check "$tmp/work/results/measure/summary.json" "$tmp/build-measure/summary.json" ||
  { cat "$tmp/out"; fail "the package's measure differs from the build tree's"; }
step "run, measure and check took $(( ($(date +%s%N) - t0) / 1000000 )) ms"

# The Python module as a user imports it: `python3 -c "import glintlab"` from the package's
# dist-packages, its data beside it, and a comparison that gives what the package's CLI gives.
step "python3 -c 'import glintlab'"
python=/usr/bin/python3
run env PYTHONPATH="$tmp/root/usr/lib/python3/dist-packages" "$python" -c "import glintlab" ||
  { cat "$tmp/out"; fail "python3 -c 'import glintlab' failed with the package's module"; }
F=$src/tests/data/flip
cp "$F/hdr_bimodal_ref.exr" "$F/hdr_bimodal_test.exr" "$F/ldr_ref.png" "$tmp/inputs/"
run "$pkg" compare "$tmp/inputs/hdr_bimodal_test.exr" "$tmp/inputs/hdr_bimodal_ref.exr" --metric flip --json ||
  { cat "$tmp/out"; fail "the package's glintlab compare failed"; }
cp "$tmp/out" "$tmp/cli-compare.json"
run env PYTHONPATH="$tmp/root/usr/lib/python3/dist-packages" "$python" -c "
import json, glintlab, sys
assert glintlab._core.data_folder() == '$tmp/root/usr/share/glintlab', glintlab._core.data_folder()
r = glintlab.compare('$tmp/inputs/hdr_bimodal_ref.exr', '$tmp/inputs/hdr_bimodal_test.exr', metrics='flip')
cli = json.load(open('$tmp/cli-compare.json'))['metrics']['flip']
assert r['flip']['mean'] == cli['mean'] and r['flip']['map'].shape == (64, 96), (r['flip']['mean'], cli)
assert glintlab.read_image('$tmp/inputs/ldr_ref.png').shape == (64, 96, 3)  # OpenImageIO, through libglintlab_oiio.so
print(glintlab.__file__)" || { cat "$tmp/out"; fail "the package's Python module does not compare as its CLI does"; }
grep -qxF "$tmp/root/usr/lib/python3/dist-packages/glintlab/__init__.py" "$tmp/out" ||
  fail "python3 imported glintlab from elsewhere: $(cat "$tmp/out")"

# ---------------------------------------------------------------- the prefix, and missing data
prefixed=$tmp/prefix/bin/glintlab
run "$prefixed" --version || { cat "$tmp/out"; fail "the prefix's glintlab --version failed"; }
grep -qxF "data: $tmp/prefix/share/glintlab (../share/glintlab beside the executable $prefixed)" "$tmp/out" ||
  fail "the prefix's glintlab does not read its data beside it:"$'\n'"$(cat "$tmp/out")"
run "$prefixed" list || { cat "$tmp/out"; fail "the prefix's glintlab list failed"; }
grep -q "thesis/fig6-7-hdri-match" "$tmp/out" || fail "the prefix's glintlab list lacks the thesis experiments"
run env PYTHONPATH="$tmp/prefix/lib/python3/dist-packages" /usr/bin/python3 -c \
  "import glintlab; print(glintlab._core.data_folder())" || { cat "$tmp/out"; fail "the prefix's Python module does not import"; }
grep -qxF "$tmp/prefix/share/glintlab" "$tmp/out" || fail "the prefix's Python module reads its data from $(cat "$tmp/out")"

mkdir -p "$tmp/lonely/bin" "$tmp/empty"
cp "$pkg" "$tmp/lonely/bin/glintlab"
rc=0; run "$tmp/lonely/bin/glintlab" run regression --out "$tmp/work/lonely" || rc=$?
[ $rc -eq 4 ] || fail "glintlab beside no data: exit $rc, not 4:"$'\n'"$(cat "$tmp/out")"
grep -qF "$tmp/lonely/share/glintlab (../share/glintlab beside the executable $tmp/lonely/bin/glintlab) has no" "$tmp/out" &&
  grep -qF "set GLINTLAB_DATA_DIR" "$tmp/out" || fail "glintlab beside no data says:"$'\n'"$(cat "$tmp/out")"
rc=0; GLINTLAB_DATA_DIR=$tmp/empty "$pkg" list > "$tmp/out" 2>&1 || rc=$?
[ $rc -eq 4 ] && grep -qF "$tmp/empty (\$GLINTLAB_DATA_DIR) has no" "$tmp/out" ||
  fail "GLINTLAB_DATA_DIR=$tmp/empty glintlab list: exit $rc:"$'\n'"$(cat "$tmp/out")"
GLINTLAB_DATA_DIR=$tmp/prefix/share/glintlab "$pkg" --version | grep -qxF "data: $tmp/prefix/share/glintlab (\$GLINTLAB_DATA_DIR)" ||
  fail "GLINTLAB_DATA_DIR does not override the package's data folder"
step "ok"
