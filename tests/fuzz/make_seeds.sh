#!/usr/bin/env bash
# Regenerates the image seeds of the compare harness (tests/fuzz/corpus/compare/) with oiiotool
# (Debian package openimageio-tools). Each seed is one selector byte (see fuzz_compare.cpp:
# bits 0-1 extension, bits 2-7 options) followed by a tiny image file. The seeds are checked in;
# run this only to change them.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
OUT="$HERE/corpus/compare"
TMP="$(mktemp -d /tmp/glintlab-fuzz-seeds-XXXXXX)"
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
GRAD="fill:topleft=0.1,0.2,0.3:topright=2,0.5,0.1:bottomleft=0,1,0.2:bottomright=0.7,0.7,4"
seed() {  # seed NAME SELECTOR_HEX FILE
  { printf "\\x$2"; cat "$3"; } > "$OUT/$1"
}
oiiotool --pattern "$GRAD" 4x4 3 -d float --compression zip -o "$TMP/a.exr"
seed exr-float-rgb-zip 00 "$TMP/a.exr"
oiiotool --pattern "$GRAD" 4x4 4 -d half --compression piz -o "$TMP/b.exr"
seed exr-half-rgba-piz-json-map 30 "$TMP/b.exr"
oiiotool --pattern "$GRAD" 3x2 1 -d float --compression none -o "$TMP/c.exr"
seed exr-y-none-csv 40 "$TMP/c.exr"
oiiotool --pattern "$GRAD" 4x4 3 -d half --compression dwaa --tile 2 2 -o "$TMP/d.exr"
seed exr-tiled-dwaa-ldr 04 "$TMP/d.exr"
oiiotool --pattern "$GRAD" 4x4 3 -d half --compression b44 --attrib oiio:ColorSpace ACEScg -o "$TMP/e.exr"
seed exr-b44-acescg-view 08 "$TMP/e.exr"
oiiotool --pattern constant:color=-1,0.5,0.25 4x4 3 -d float --compression rle -o "$TMP/f.exr"
seed exr-negative-rle-json 10 "$TMP/f.exr"
oiiotool --pattern "$GRAD" 4x4 3 -d uint8 -o "$TMP/g.png"
seed png-rgb8 01 "$TMP/g.png"
oiiotool --pattern "$GRAD" 4x4 2 -d uint16 -o "$TMP/h.png"
seed png-ga16-json 11 "$TMP/h.png"
oiiotool --pattern "$GRAD" 2x3 4 -d uint8 -o "$TMP/i.png"
seed png-rgba8-asref-csv c1 "$TMP/i.png"
oiiotool --pattern "$GRAD" 4x4 3 -o "$TMP/j.hdr"
seed hdr-rgbe 02 "$TMP/j.hdr"
oiiotool --pattern "$GRAD" 4x4 3 -o "$TMP/k.hdr"
seed hdr-rgbe-view-ldr-map 2e "$TMP/k.hdr"
oiiotool --pattern fill:topleft=0.0001,0.0001,0.0001:bottomright=10000,5000,20000 8x8 3 -d float -o "$TMP/l.exr"
seed exr-hdr-range-asref 80 "$TMP/l.exr"
oiiotool --pattern fill:topleft=0,0,0:bottomright=1,1,1 5x3 3 -d half --tile 4 4 -o "$TMP/m.exr"
seed exr-tiled-asref-json-map b0 "$TMP/m.exr"
ls -l "$OUT"
