#!/usr/bin/env bash
# The measured-surface chain (README, "Measured surfaces"):
#   two scans of one surface at two magnifications (.x3p)
#   -> their statistics and PSDs (plane removed, Hann window, trusted band)
#   -> the low-magnification scan solved as it is (a finite pad on its own
#      pixels) with Persson's theory beside it
#   -> one stitched PSD -> a synthetic periodic surface following it
#   -> a sliding-contact solve on that surface and its refinement study.
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

# 3. The low-magnification scan solved as it is (configs/measured_scan.toml):
#    plane removed, non-periodic; summary.json has Persson's friction and area
#    from the scan's windowed PSD over its trusted band, beside the solve's.
$VS solve configs/measured_scan.toml --set "surface.file=\"$(realpath "$OUT")/scan_low.x3p\"" --out "$OUT/scan_solve"
$VS persson configs/measured_scan.toml --set "surface.file=\"$(realpath "$OUT")/scan_low.x3p\"" --speeds 1e-4,1,40 --out "$OUT/scan_persson"

# 4. One PSD from both scans, each over its trusted band.
$VS surface psd-stitch "$OUT/scan_low.x3p" "$OUT/scan_high.x3p" --fill-missing --out "$OUT/stitched"

# 5. A periodic surface following the stitched PSD, the solve on it, and
#    the refinement study of that solve (Richardson verdict in refine.json).
PSD="surface.generate.psd=\"$(realpath "$OUT")/stitched/psd.csv\""
$VS surface generate --config configs/measured_example.toml --set "$PSD" --out "$OUT/surface"
$VS solve configs/measured_example.toml --set "$PSD" --out "$OUT/solve"
$VS refine configs/measured_example.toml --set "$PSD" --levels 64,128,256 --out "$OUT/refine"

ms=$((($(date +%s%N) - start) / 1000000))
echo "chain done in $((ms / 1000)).$((ms % 1000 / 100)) s: figures $OUT/stitched/psd.png, $OUT/surface/psd.png; solves $OUT/scan_solve/, $OUT/solve/, $OUT/refine/"
