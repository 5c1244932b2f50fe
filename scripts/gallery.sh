#!/usr/bin/env bash
# gallery.sh — regenerates docs/gallery/: the 1988 report's Appendix A (terrains 1-8 as orthographic profile
# plots of 513 x 513 grids, every 8th profile), a colour relief for the README, and growth frames.
# Usage: scripts/gallery.sh [path/to/fracterra]   (default build/release/fracterra; run scripts/build.sh first)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${1:-build/release/fracterra}
OUT=docs/gallery
[ -x "$BIN" ] || { echo "gallery.sh: $BIN not found; run scripts/build.sh first" >&2; exit 1; }
mkdir -p "$OUT"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The report displaces a new point by a Gaussian scaled by delta^(3-D) with delta in grid spacings, so its heights
# are in grid-spacing units and its dilations (0.05 .. 0.8) apply to those. fracterra's delta is in units of the
# whole square (docs/ALGORITHM.md §3), so sigma = 512^H gives the report's units on a 513 x 513 grid.
sigma_for() { awk -v d="$1" 'BEGIN { printf "%.6f", 512 ^ (3 - d) }'; }

# terrain NAME D DILATION SEED
terrain() {
    local name=$1 d=$2 dil=$3 seed=$4
    local f="$tmp/D$d-s$seed.f32"
    [ -e "$f" ] || "$BIN" generate -q --levels 9 --dimension "$d" --sigma "$(sigma_for "$d")" --seed "$seed" \
        --backend cpu -o "$f"
    "$BIN" render -q "$f" --style profiles --every 8 --dilation "$dil" --base 10 --width 1200 -o "$OUT/$name.png"
    printf '| %s | %s | %s | %s | %s |\n' "$name" "$d" "$(awk -v d="$d" 'BEGIN { print 3 - d }')" "$dil" "$seed"
}

{
    echo "| picture | D | H | dilation | seed |"
    echo "|---|---|---|---|---|"
    # Terrains 1-3: the same random numbers, D = 2.05, growing vertical dilation.
    terrain terrain-1 2.05 0.05 1988
    terrain terrain-2 2.05 0.1 1988
    terrain terrain-3 2.05 0.2 1988
    # Terrains 4-8: one seed, growing D, the dilation growing with it as in the report.
    terrain terrain-4 2.05 0.05 513
    terrain terrain-5 2.1 0.1 513
    terrain terrain-6 2.2 0.2 513
    terrain terrain-7 2.4 0.4 513
    terrain terrain-8 2.8 0.8 513
} > "$OUT/parameters.md"

# A vector version of one plot, for publication use.
"$BIN" render -q "$tmp/D2.2-s513.f32" --style profiles --every 8 --dilation 0.2 --base 10 -o "$OUT/terrain-6.svg"

# Colour relief and grey hillshade of a 513 x 513 terrain (the README's picture).
"$BIN" generate -q --levels 9 --hurst 0.8 --seed 7 --backend cpu -o "$tmp/relief.npy"
"$BIN" render -q "$tmp/relief.npy" --style color -o "$OUT/relief-color.png"
"$BIN" render -q "$tmp/relief.npy" --style hillshade -o "$OUT/relief-hillshade.png"

# The thesis's growth, level by level, as one animated GIF.
"$BIN" generate -q --levels 8 --hurst 0.7 --seed 11 --backend cpu --gif "$OUT/growth.gif"

# Densify (issue 5): a rough sketch of 33 x 33 heights (two ridges and a valley, 480 m apart) filled to 513 x 513
# (30 m). Before: the sketch alone (sigma ~ 0: the contract's midpoint interpolation); after: fractal detail with
# H 0.8 and sigma 250 m. Both rendered with the same z-factor so that only the detail differs.
/usr/bin/python3 - "$tmp/sketch.npy" <<'PYEOF'
import sys, numpy as np
y, x = np.mgrid[0:33, 0:33] / 32.0
h = 900 * np.exp(-((x - 0.3) ** 2 / 0.02 + (y - 0.35) ** 2 / 0.2)) + 700 * np.exp(-((x - 0.75) ** 2 / 0.03 + (y - 0.6) ** 2 / 0.12))
h += 250 * (1 - y) - 150 * np.exp(-((x - 0.52) ** 2) / 0.004)
np.save(sys.argv[1], h.astype(np.float32))
PYEOF
"$BIN" generate -q --levels 9 --coarse "$tmp/sketch.npy" --spacing 30 --hurst 0.8 --sigma 1e-6 --seed 5 --backend cpu -o "$tmp/before.npy"
"$BIN" generate -q --levels 9 --coarse "$tmp/sketch.npy" --spacing 30 --hurst 0.8 --sigma 250 --seed 5 --backend cpu -o "$tmp/after.npy"
"$BIN" render -q "$tmp/before.npy" --style color --z-factor 1 -o "$OUT/densify-before.png"
"$BIN" render -q "$tmp/after.npy" --style color --z-factor 1 -o "$OUT/densify-after.png"

echo "gallery.sh: wrote $(ls "$OUT" | wc -l) files to $OUT" >&2
