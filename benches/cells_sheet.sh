#!/usr/bin/env bash
# The before/after sheet of the cells (samples/cells-before-after.jpg): each shared photo in
# every cell look, the paper's cells (cells.kind=voronoi, odd rows) above the default
# edge-following cells (even rows). Not a test; regenerate it after a change to the cells.
#
# Usage: benches/cells_sheet.sh [OUT.jpg]     (default samples/cells-before-after.jpg)
#   PYTHON  a Python with pillow, to stack the rows (default python3)
#   PHOTOS  folder of photos (default ../shared/photos)
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
PHOTOS=${PHOTOS:-../shared/photos}
OUT=${1:-samples/cells-before-after.jpg}
LOOKS=mosaic,pen-hatch,crosshatch,strokes,pointillist,glyphs,engraving
cargo build --release --quiet
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rows=()
for photo in "$PHOTOS"/*.png; do
  name=$(basename "${photo%.*}")
  for cells in voronoi edges; do
    ./target/release/anisopaint contact-sheet "$photo" -s "$LOOKS" --set "cells.kind=$cells" \
      --columns 7 --tile-width 118 --seed 7 -q -o "$tmp/$name-$cells.png"
    rows+=("$tmp/$name-$cells.png")
  done
done
"$PYTHON" benches/stack_rows.py "$OUT" "${rows[@]}"
echo "wrote $OUT"
