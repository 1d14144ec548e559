#!/usr/bin/env bash
# Whole processes side by side with their peers, on this machine, in one run:
#   1. the sampler against BAMG (Debian package freefem++, `ffbamg`) on the rotating 4:1 field
#      of about 11 000 ellipses: wall time (RUNS alternating pairs: the median of each and of
#      the pairs' ratios), and the packing of both measured by
#      benches/packing.py (coverage, overlap, count, nearest-neighbour d), which imports nothing
#      from the crate;
#   2. one million samples (constant 2:1 metric, semi-axes 3 and 1.5 px, 4096² .npy): wall time
#      and peak memory of `anisopaint sample --out`;
#   3. `paint -s mosaic` of a 2048² photo against `gegl:mosaic tile-size=15` (Debian package
#      gegl), in alternating pairs as 1;
#   4. `batch --jobs 2` against GNU parallel -j2 running single paints (Debian package
#      parallel) over 24 one-megapixel photos.
#
# Usage: benches/peers.sh [sampler|million|mosaic|batch ...]   (default: all four)
#   PYTHON  a Python with numpy, scipy, scikit-image and pillow (default: python3)
#   RUNS    repetitions for medians (default: 5)
#   KEEP    a folder to keep the inputs and outputs in (default: a temporary one)
# Not a test: it prints figures to compare before and after a change.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
RUNS=${RUNS:-5}
cargo build --release --quiet
bin=$PWD/target/release/anisopaint
packing=$PWD/benches/packing.py
photos=$PWD/../shared/photos
if [ -n "${KEEP:-}" ]; then
  work=$KEEP
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
cd "$work"
what=("$@")
[ ${#what[@]} -gt 0 ] || what=(sampler million mosaic batch)

# Median wall seconds of RUNS runs of a command (GNU time), and the last run's peak RSS in MB.
timed() {
  local walls=() rss=0
  for _ in $(seq "$RUNS"); do
    /usr/bin/time -f '%e %M' -o t.txt "$@" >/dev/null 2>&1
    read -r wall kb <t.txt
    walls+=("$wall")
    rss=$((kb / 1024))
  done
  printf '%s %s\n' "$(printf '%s\n' "${walls[@]}" | sort -g | sed -n "$(((RUNS + 1) / 2))p")" "$rss"
}

# Two commands (strings for sh) run alternately RUNS times, so each pair sees the machine at
# the same moment (on a shared VM its speed drifts by tens of per cent over minutes): the
# median wall of each, the median of the pairs' ratios (first / second), and each one's last
# peak RSS in MB.
paired() {
  local a=() b=() r=() rss_a=0 rss_b=0
  for _ in $(seq "$RUNS"); do
    /usr/bin/time -f '%e %M' -o t.txt sh -c "exec $1" >/dev/null 2>&1
    read -r wa kb <t.txt
    rss_a=$((kb / 1024))
    /usr/bin/time -f '%e %M' -o t.txt sh -c "exec $2" >/dev/null 2>&1
    read -r wb kb <t.txt
    rss_b=$((kb / 1024))
    a+=("$wa")
    b+=("$wb")
    r+=("$(echo "scale=3; $wa / $wb" | bc)")
  done
  local mid=$(((RUNS + 1) / 2))
  median() { printf '%s\n' "$@" | sort -g | sed -n "${mid}p"; }
  printf '%s %s %s %s %s\n' "$(median "${a[@]}")" "$rss_a" "$(median "${b[@]}")" "$rss_b" "$(median "${r[@]}")"
}

for w in "${what[@]}"; do
  case $w in
  sampler)
    "$PYTHON" "$packing" field rotating rot.npy
    "$PYTHON" "$packing" bamg-inputs rot.npy .
    read -r ours ours_mb bamg bamg_mb ratio < <(paired "$bin sample rot.npy -q --out ours.csv" \
      "ffbamg -b bg.mesh -M bg.mtr -o bamg.mesh")
    read -r lat lat_mb < <(timed "$bin" sample rot.npy -q --out lattice.csv --set sampler.seeding=darts)
    "$PYTHON" "$packing" bamg-samples bamg.mesh rot.npy bamg.csv
    echo "rotating 4:1 field, 11 000 ellipses, median wall of $RUNS"
    echo "  anisopaint sample: $ours s, $ours_mb MB; $("$PYTHON" "$packing" eval ours.csv rot.npy)"
    echo "  ... darts seed:    $lat s, $lat_mb MB; $("$PYTHON" "$packing" eval lattice.csv rot.npy)"
    echo "  BAMG (ffbamg):     $bamg s, $bamg_mb MB; $("$PYTHON" "$packing" eval bamg.csv rot.npy)"
    echo "  ratio ours / BAMG: $ratio (median of $RUNS alternating pairs)"
    ;;
  million)
    "$PYTHON" "$packing" field constant2 c2.npy --side 4096
    for seeding in auto darts; do
      RUNS=1 timed "$bin" sample c2.npy -q --out c2.csv --set sampler.seeding=$seeding >m.txt
      read -r wall mb <m.txt
      echo "1 M samples (4096², constant 2:1), $seeding: $wall s, $mb MB peak; $("$PYTHON" "$packing" eval c2.csv c2.npy --nn-only)"
    done
    ;;
  mosaic)
    "$PYTHON" -c "from PIL import Image; Image.open('$photos/coffee.png').convert('RGB').resize((2048, 2048), Image.BICUBIC).save('p2048.png')"
    read -r ours ours_mb gegl gegl_mb ratio < <(paired "$bin paint p2048.png -s mosaic -q -o ours2048.png" \
      "gegl p2048.png -o gegl2048.png -- gegl:mosaic tile-size=15 seed=1")
    echo "2048² mosaic, median wall of $RUNS alternating pairs: anisopaint $ours s ($ours_mb MB), GEGL $gegl s ($gegl_mb MB), ratio $ratio"
    ;;
  batch)
    mkdir -p in out_batch out_parallel
    "$PYTHON" - "$photos" <<'EOF'
import sys, os
from PIL import Image
names = sorted(n for n in os.listdir(sys.argv[1]) if n.endswith('.png'))
for i in range(24):
    im = Image.open(os.path.join(sys.argv[1], names[i % len(names)])).convert('RGB')
    # about a megapixel, a different crop of each photo so no two files are alike
    im = im.resize((1224, 816), Image.BICUBIC).rotate(7 * i, expand=False)
    im.save(f'in/p{i:02d}.png')
EOF
    read -r ours ours_mb < <(timed "$bin" batch in -s mosaic -o out_batch --jobs 2 -q --force)
    read -r par par_mb < <(timed sh -c "ls in/*.png | parallel -j2 '$bin paint {} -s mosaic -q -o out_parallel/{/}'")
    echo "24 one-megapixel photos, mosaic, median wall of $RUNS: batch --jobs 2 $ours s ($ours_mb MB), parallel -j2 $par s, ratio $(echo "scale=2; $ours / $par" | bc)"
    ;;
  *)
    echo "unknown: $w (sampler, million, mosaic, batch)" >&2
    exit 2
    ;;
  esac
done
