#!/bin/sh
# Render the Blender Cycles test sequences (see make_sequence.py) into OUT,
# by default this folder: OUT/{spp1,spp4,spp16,ref}/frame_0001.exr ...
#
#   tests/data/blender/make.sh [OUT] [-- extra make_sequence.py options]
#
# Needs Blender 3.4 (Debian 12: apt-get install --no-install-recommends blender).
# Takes about a minute on 2 idle CPU cores (almost all of it the 4096-spp ref).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$here}
[ $# -gt 0 ] && shift
[ "${1:-}" = "--" ] && shift
command -v blender >/dev/null 2>&1 || {
    echo "make.sh: blender not found (apt-get install --no-install-recommends blender)" >&2
    exit 1
}
mkdir -p "$out"
exec blender -b --factory-startup -noaudio --python-exit-code 1 \
    --python "$here/make_sequence.py" -- --out "$out" "$@"
