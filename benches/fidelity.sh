#!/usr/bin/env bash
# Fidelity of the cells at equal cell count, measured by the independent evaluator
# ../shared/tools/fidelity.py: every cell replaced by its mean colour against the photo (PSNR over
# RGB, SSIM over luma), beside an isotropic CVT and SLIC superpixels with the same count. Also
# counts how many connected pieces the cells fall into (a partition, not a posterization).
#
# Usage: benches/fidelity.sh [STYLE] [--set KEY=VALUE ...]     (default STYLE: mosaic)
#   PYTHON    a Python with numpy, scipy, scikit-image and pillow (default: python3), e.g.
#             python3 -m venv /tmp/venv && /tmp/venv/bin/pip install numpy scipy scikit-image pillow
#   PHOTOS    folder of photos (default: ../shared/photos)
# Not a test: it prints a table to compare before and after a change.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
PHOTOS=${PHOTOS:-../shared/photos}
STYLE=${1:-mosaic}
shift || true
cargo build --release --quiet
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf '%-10s %6s | %-14s | %-14s | %-20s | %s\n' photo cells "ours PSNR/SSIM" "CVT PSNR/SSIM" "SLIC PSNR/SSIM (N)" "pieces"
for photo in "$PHOTOS"/*.png "$PHOTOS"/*.jpg; do
  [ -e "$photo" ] || continue
  name=$(basename "${photo%.*}")
  ./target/release/anisopaint render "$photo" -s "$STYLE" --seed 7 -q -o "$out/$name.png" \
    --labels "$out/$name.npy" "$@"
  line=$("$PYTHON" ../shared/tools/fidelity.py "$photo" "$out/$name.npy")
  pieces=$("$PYTHON" - "$out/$name.npy" <<'EOF'
import sys, numpy as np
from skimage.measure import label
L = np.load(sys.argv[1])
print(f"{label(L + 1, connectivity=1, background=0).max()} pieces of {len(np.unique(L))} cells")
EOF
)
  echo "$line" | sed -E 's/N=([0-9]+) ours psnr=([0-9.]+) ssim=([0-9.]+) \| cvt psnr=([0-9.]+) ssim=([0-9.]+) \| slic\(N=([0-9]+)\) psnr=([0-9.]+) ssim=([0-9.]+)/\1 \2 \3 \4 \5 \6 \7 \8/' |
    while read -r n op os cp cs sn sp ss; do
      printf '%-10s %6s | %6s / %5s | %6s / %5s | %6s / %5s (%s) | %s\n' "$name" "$n" "$op" "$os" "$cp" "$cs" "$sp" "$ss" "$sn" "$pieces"
    done
done
