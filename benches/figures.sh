#!/usr/bin/env bash
# The paper's figures from the analytic fields: samples/figures/, shown in
# README.md. Glyphs and fabric of a stress field with a compressive and a tensile point load
# (paper Figures 5 and 7: elongated ellipses and thin fibres near the loads, following the
# stress trajectories), and glyphs, line texture and fabric around a degenerate point (paper
# Figure 6). Not a test; regenerate after a change to the mapping or the looks.
#
# Usage: benches/figures.sh [OUTDIR]     (default samples/figures)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-samples/figures}
mkdir -p "$OUT"
cargo build --release --quiet
paint() { # field style name [--set ...]
  local field=$1 style=$2 name=$3
  shift 3
  ./target/release/anisopaint paint "analytic:$field" -s "$style" --width 384 --height 384 \
    --seed 7 -q -o "$OUT/$name.jpg" "$@"
}
paint two-point-load glyphs two-point-load.glyphs
paint two-point-load fabric two-point-load.fabric
paint two-point-load pen-hatch two-point-load.hatch
paint degenerate-point glyphs degenerate-point.glyphs
paint degenerate-point fabric degenerate-point.fabric
paint degenerate-point pen-hatch degenerate-point.line --set look.kind=line
ls -l "$OUT"
