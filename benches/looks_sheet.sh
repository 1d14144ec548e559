#!/usr/bin/env bash
# The contact sheet of every look on the shared photos (samples/looks.jpg): one row per photo,
# one column per built-in preset, through `anisopaint contact-sheet`. Not a test; regenerate it
# after a change to the looks.
#
# Usage: benches/looks_sheet.sh [OUT.jpg]     (default samples/looks.jpg)
#   PYTHON  a Python with pillow, to stack the rows (default python3)
#   PHOTOS  folder of photos (default ../shared/photos)
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
PHOTOS=${PHOTOS:-../shared/photos}
OUT=${1:-samples/looks.jpg}
cargo build --release --quiet
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rows=()
for photo in "$PHOTOS"/*.png; do
  name=$(basename "${photo%.*}")
  ./target/release/anisopaint contact-sheet "$photo" --columns 9 --tile-width 150 --seed 7 -q \
    -o "$tmp/$name.png"
  rows+=("$tmp/$name.png")
done
"$PYTHON" benches/stack_rows.py "$OUT" "${rows[@]}"
echo "wrote $OUT"
