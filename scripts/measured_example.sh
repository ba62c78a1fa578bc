#!/usr/bin/env bash
# The measured-surface chain (README, "Measured surfaces"):
#   two scans of one surface at two magnifications (.x3p)
#   -> their statistics and PSDs -> one stitched PSD
#   -> a synthetic periodic surface following it -> a sliding-contact solve.
# Usage: scripts/measured_example.sh [OUT_DIR]   (default out/measured; the
# shipped config configs/measured_example.toml reads out/measured).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/measured}
cargo build --release --quiet --bin viscoslide --example measured_scans
VS=target/release/viscoslide
rm -rf "$OUT"
start=$(date +%s%N)

# 1. The data set: scan_low.x3p, scan_high.x3p (and the true PSD, for comparison).
target/release/examples/measured_scans "$OUT"

# 2. Statistics of each scan (plane removed, Hann window; the high
#    magnification scan has invalid points, filled by harmonic interpolation).
$VS surface stats "$OUT/scan_low.x3p" --out "$OUT/stats_low"
$VS surface stats "$OUT/scan_high.x3p" --fill-missing --out "$OUT/stats_high"

# 3. One PSD from both scans, each over its trusted band.
$VS surface psd-stitch "$OUT/scan_low.x3p" "$OUT/scan_high.x3p" --fill-missing --out "$OUT/stitched"

# 4. A periodic surface following the stitched PSD, and the solve on it.
PSD="surface.generate.psd=\"$(realpath "$OUT")/stitched/psd.csv\""
$VS surface generate --config configs/measured_example.toml --set "$PSD" --out "$OUT/surface"
$VS solve configs/measured_example.toml --set "$PSD" --out "$OUT/solve"

ms=$((($(date +%s%N) - start) / 1000000))
echo "chain done in $((ms / 1000)).$((ms % 1000 / 100)) s: figures $OUT/stitched/psd.png, $OUT/surface/psd.png, $OUT/solve/"
