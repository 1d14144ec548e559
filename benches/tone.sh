#!/usr/bin/env bash
# Tone and edges of the textured looks against G'MIC's counterparts, measured by the
# independent evaluator ../shared/tools/tone.py (luma blurred at 2 px: PSNR, SSIM, and edge
# recall, the share of the photo's strongest edges that survive in place and direction).
#
#   strokes            against  fx_brushify
#   pen-hatch, crosshatch       pencilbw
#   engraving                   fx_engrave
#   pointillist, glyphs         the issue's target (blurred SSIM >= 0.75)
#
# Usage: benches/tone.sh [STYLE ...]        (default: every look above and its peer)
#   PYTHON  a Python with numpy, scipy, scikit-image and pillow (default python3)
#   PHOTOS  folder of photos (default ../shared/photos)
#   KEEP    a folder to keep every picture in, to look at them side by side
#   PEERS=0 skips G'MIC (its pictures are cached in KEEP when KEEP is set)
# G'MIC is the Debian package `gmic`; its commands are those of ../shared/tools/README.md.
# Photos with alpha are flattened over white before G'MIC sees them. Not a test: it prints a
# table to compare before and after a change.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
PHOTOS=${PHOTOS:-../shared/photos}
PEERS=${PEERS:-1}
STYLES=("$@")
[ ${#STYLES[@]} -gt 0 ] || STYLES=(strokes pen-hatch crosshatch engraving pointillist glyphs)
cargo build --release --quiet
if [ -n "${KEEP:-}" ]; then out=$KEEP; mkdir -p "$out"; else
  out=$(mktemp -d); trap 'rm -rf "$out"' EXIT; fi

peer_of() {
  case $1 in
    strokes) echo brushify ;;
    pen-hatch | crosshatch) echo pencilbw ;;
    engraving) echo engrave ;;
    *) echo - ;;
  esac
}
peer_run() { # peer in out
  case $1 in
    brushify) gmic -v - "$2" fx_brushify 7,0.25,4,64,25,12,0,2,4,0.2,0.5,30,1,1,1,5,0,0.2,1 -o "$3" ;;
    pencilbw) gmic -v - "$2" pencilbw , -o "$3" ;;
    engrave) gmic -v - "$2" fx_engrave 0.5,50,0,8,40,0,0,0,10,1,0,0,0,1,0 -o "$3" ;;
  esac
}
measure() { # photo picture -> "recall ssim psnr"
  "$PYTHON" ../shared/tools/tone.py "$1" "$2" |
    sed -E 's/.*blur_psnr=([0-9.-]+) blur_ssim=([0-9.-]+) edge_recall=([0-9.-]+)/\3 \2 \1/'
}

printf '%-11s %-10s | %-22s | %-22s | %s\n' look photo "ours recall/SSIM/PSNR" "peer recall/SSIM/PSNR" verdict
for style in "${STYLES[@]}"; do
  peer=$(peer_of "$style")
  for photo in "$PHOTOS"/*.png "$PHOTOS"/*.jpg; do
    [ -e "$photo" ] || continue
    name=$(basename "${photo%.*}")
    flat="$out/$name.flat.png"
    [ -e "$flat" ] || "$PYTHON" - "$photo" "$flat" <<'EOF'
import sys
from PIL import Image
im = Image.open(sys.argv[1])
if im.mode in ("RGBA", "LA", "P"):
    bg = Image.new("RGBA", im.size, (255, 255, 255, 255)); bg.alpha_composite(im.convert("RGBA")); im = bg
im.convert("RGB").save(sys.argv[2])
EOF
    ./target/release/anisopaint paint "$photo" -s "$style" --seed 7 -q -o "$out/$name.$style.png"
    read -r r s p <<<"$(measure "$flat" "$out/$name.$style.png")"
    verdict=""
    if [ "$peer" = - ]; then
      pr=- ps=- pp=-
      verdict=$("$PYTHON" -c "print('ok' if $s >= 0.75 else 'below 0.75')")
    else
      pic="$out/$name.$peer.png"
      if [ "$PEERS" = 1 ] && [ ! -e "$pic" ]; then peer_run "$peer" "$flat" "$pic" >/dev/null 2>&1; fi
      if [ -e "$pic" ]; then
        read -r pr ps pp <<<"$(measure "$flat" "$pic")"
        verdict=$("$PYTHON" -c "print(('recall ok' if $r >= $pr else 'recall below') + ', ' + ('SSIM ok' if $s >= $ps else 'SSIM below'))")
      else pr=- ps=- pp=-; fi
    fi
    printf '%-11s %-10s | %5s / %5s / %5s  | %5s / %5s / %5s  | %s %s\n' \
      "$style" "$name" "$r" "$s" "$p" "$pr" "$ps" "$pp" "$peer" "$verdict"
  done
done
