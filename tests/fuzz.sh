#!/usr/bin/env bash
# The long fuzz campaign of tests/fuzz.rs: every image decoder path, the .npy reader
# and the preset parser, CASES mutated files each (default 100 000), from a new SEED each run
# (default: the time), in release mode. A failure prints the case seed that replays it:
#   FUZZ_SEED=<seed> FUZZ_CASES=<n> cargo test --release --test fuzz
# Not part of `cargo test`, which runs 300 cases per target with a fixed seed.
#
# Usage: tests/fuzz.sh [CASES] [SEED]
set -euo pipefail
cd "$(dirname "$0")/.."
export FUZZ_CASES=${1:-100000}
export FUZZ_SEED=${2:-$(date +%s)}
echo "fuzz: $FUZZ_CASES cases per target, seed $FUZZ_SEED"
cargo test --release --test fuzz -- --nocapture --test-threads 3 2>&1 | grep -E '^fuzz |panicked|took|test result'
