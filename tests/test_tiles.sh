#!/usr/bin/env bash
# test_tiles.sh — host/cli_tiles.c: `fracterra tiles` end to end: tiles from several processes stitch, bit for bit,
# into the whole grid; index.json; shared quantisation range; XYZ pyramid levels are exact subsamples; N = 24;
# bad input fails with one line and writes nothing.
# Usage: test_tiles.sh PATH/TO/fracterra   (needs /usr/bin/python3 with numpy; skips, exit 77, without)
set -u
BIN=$1
T=$(mktemp -d /tmp/frt_tiles_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
check() { if eval "$1"; then ok; else bad "$2"; fi; }
PY=/usr/bin/python3
if ! "$PY" -c 'import numpy' 2>/dev/null; then
    echo "test_tiles: /usr/bin/python3 with numpy is needed; skipped"
    exit 77
fi
# Vulkan runs use the validation layer when installed; any message fails the test.
export FRT_VALIDATION=${FRT_CLI_VALIDATION:-1}
export FRT_PROGRESS=never

# Python helpers: read tiles of any format, stitch them, decode PNG (no PIL here).
cat > "$T/tl.py" <<'PYEOF'
import json, struct, zlib
import numpy as np

def png(path):
    """(samples as uint16 array, text chunks) of a greyscale PNG."""
    d = open(path, "rb").read()
    assert d[:8] == b"\x89PNG\r\n\x1a\n", path
    i, idat, text = 8, b"", {}
    while i < len(d):
        n, = struct.unpack(">I", d[i:i + 4]); kind = d[i + 4:i + 8]; body = d[i + 8:i + 8 + n]; i += 12 + n
        if kind == b"IHDR":
            w, h, bits, color = struct.unpack(">IIBB", body[:10])
            assert color == 0, (path, color)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"tEXt":
            k, v = body.split(b"\0", 1); text[k.decode()] = v.decode()
    bpp = bits // 8
    raw = zlib.decompress(idat); stride = w * bpp
    out = np.zeros((h, stride), np.int32); prev = np.zeros(stride, np.int32)
    for y in range(h):
        f = raw[y * (stride + 1)]; line = np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int32)
        cur = np.zeros(stride, np.int32)
        for x in range(stride):
            a = cur[x - bpp] if x >= bpp else 0; b = prev[x]; c = prev[x - bpp] if x >= bpp else 0
            if f == 0: p = 0
            elif f == 1: p = a
            elif f == 2: p = b
            elif f == 3: p = (a + b) // 2
            else:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            cur[x] = (line[x] + p) & 255
        out[y] = cur; prev = cur
    s = out.reshape(h, w, bpp)
    v = s[:, :, 0] * 256 + s[:, :, 1] if bpp == 2 else s[:, :, 0]
    return v.astype(np.uint16), text, bits

def pgm(path):
    d = open(path, "rb").read()
    assert d[:2] == b"P5"
    fields, comments, i = [], [], 2
    while len(fields) < 3:
        while d[i:i + 1].isspace(): i += 1
        if d[i:i + 1] == b"#":
            j = d.index(b"\n", i); comments.append(d[i + 1:j].decode()); i = j + 1; continue
        j = i
        while not d[j:j + 1].isspace(): j += 1
        fields.append(int(d[i:j])); i = j
    w, h, maxv = fields
    dt = ">u2" if maxv > 255 else "u1"
    return np.frombuffer(d, dt, w * h, i + 1).reshape(h, w).astype(np.uint16), comments, maxv

def tile(d, fmt, r, c):
    p = "%s/%d/%d.%s" % (d, r, c, fmt)
    if fmt == "f32":
        m = json.load(open(p + ".json"))
        return np.fromfile(p, "<f4").reshape(m["height"], m["width"])
    if fmt == "npy":
        return np.load(p)
    return png(p)[0] if fmt == "png" else pgm(p)[0]

def stitch(d, fmt):
    ix = json.load(open(d + "/index.json"))
    t, p = ix["tile"], ix["tiles_per_side"]
    first = tile(d, fmt, 0, 0)
    out = np.zeros((p * t + 1, p * t + 1), first.dtype)
    for r in range(p):
        for c in range(p):
            a = tile(d, fmt, r, c)
            assert a.shape == (t + 1, t + 1), (r, c, a.shape)
            out[r * t:r * t + t + 1, c * t:c * t + t + 1] = a
    return out, ix

def bits_equal(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))

def whole(path, periodic):
    """The grid as the tiles see it: a periodic grid repeats its first row and column after the last."""
    w = np.load(path) if path.endswith(".npy") else None
    return np.pad(w, ((0, 1), (0, 1)), mode="wrap") if periodic else w

def check_stitch(d, w, edge, fmt="f32"):
    s, ix = stitch(d, fmt)
    ref = whole(w, edge == "periodic")
    assert bits_equal(s, ref), np.abs(s - ref).max()

def check_borders(d, fmt="f32"):
    p = json.load(open(d + "/index.json"))["tiles_per_side"]
    u = lambda a: a.view(np.uint32)
    for r in range(p):
        for c in range(p):
            a = tile(d, fmt, r, c)
            if c + 1 < p: assert np.array_equal(u(a[:, -1]), u(tile(d, fmt, r, c + 1)[:, 0])), (r, c)
            if r + 1 < p: assert np.array_equal(u(a[-1, :]), u(tile(d, fmt, r + 1, c)[0, :])), (r, c)

def quantise(v, lo, hi, maxq):
    """frt_quantise: round((v - min) / (max - min) * maxq), clamped; in double, as the writer does."""
    lo, hi = float(np.float32(lo)), float(np.float32(hi))
    t = (v.astype(np.float64) - lo) / (hi - lo) * maxq + 0.5
    return np.clip(np.floor(t), 0, maxq).astype(np.uint16)
PYEOF
export PYTHONPATH=$T

# ---- help and manual ----
"$BIN" --help | grep -q 'tiles' && ok || bad "fracterra --help names tiles"
"$BIN" tiles --help > "$T/help" && grep -q -- '--only' "$T/help" && grep -q -- '--pyramid' "$T/help" && ok || bad "tiles --help"
MAN=$(dirname "$0")/../docs/fracterra.1
for opt in $(grep -oE -- '--[a-z][a-z0-9-]+' "$T/help" | sort -u); do
    grep -q -- "$(printf '%s' "$opt" | sed 's/-/\\\\-/g')" "$MAN" && ok || bad "docs/fracterra.1 lacks tiles $opt"
done
check 'grep -q "^\.SS tiles" "$MAN"' "docs/fracterra.1 has a tiles section"

# ---- tiles from K = 3 concurrent processes stitch exactly into the whole grid ----
# N = 7, T = 16: 8 x 8 tiles of 17 x 17. `shares DIR ARGS...` runs the three shares at once.
shares() {
    local dir=$1 rc=0 i
    shift
    for i in 0 1 2; do
        "$BIN" tiles "$@" --out "$dir" --only $i/3 -q 2> "$T/err.$i" &
    done
    for i in 0 1 2; do
        wait -n || rc=1
    done
    cat "$T"/err.[012] > "$T/err"
    return $rc
}
for edge in ffc periodic; do
    "$BIN" generate --levels 7 --hurst 0.6 --seed 77 --edge $edge --backend cpu -q -o "$T/whole_$edge.npy" &&
        ok || bad "generate the whole $edge grid"
    for backend in cpu auto; do
        d=$T/t_${edge}_$backend
        shares "$d" --levels 7 --tile 16 --hurst 0.6 --seed 77 --edge $edge --backend $backend &&
            ok || bad "3 shares, $edge, $backend: $(cat "$T/err")"
        check '[ ! -s "$T/err" ]' "3 shares, $edge, $backend: quiet, no validation messages: $(cat "$T/err")"
        "$PY" -c 'import sys, tl; tl.check_stitch(*sys.argv[1:])' "$d" "$T/whole_$edge.npy" $edge &&
            ok || bad "$edge $backend tiles stitch into the whole grid"
        "$PY" -c 'import sys, tl; tl.check_borders(sys.argv[1])' "$d" && ok || bad "$edge $backend: shared borders agree"
        check '[ "$(ls "$d" | wc -l)" = 9 ] && [ "$(find "$d" -name "*.f32" | wc -l)" = 64 ] && [ -z "$(find "$d" -name "*tmp-*")" ]' \
            "$edge $backend: 8 row directories, index.json, 64 tiles, no temporary files: $(ls "$d")"
    done
    # The checks can fail: one inner sample and one border sample of one tile one ulp off.
    cp -r "$T/t_${edge}_cpu" "$T/bad_$edge"
    "$PY" -c 'import sys, numpy as np; p = sys.argv[1] + "/3/5.f32"; a = np.fromfile(p, "<u4"); a[8 * 17 + 8] ^= 1; a[16 * 17 + 16] ^= 1; a.tofile(p)' "$T/bad_$edge"
    check '! "$PY" -c "import sys, tl; tl.check_stitch(*sys.argv[1:])" "$T/bad_$edge" "$T/whole_$edge.npy" $edge 2> /dev/null' \
        "$edge: the stitch check notices one ulp"
    check '! "$PY" -c "import sys, tl; tl.check_borders(sys.argv[1])" "$T/bad_$edge" 2> /dev/null' "$edge: the border check notices one ulp"
    # Periodic: the last tile's border wraps to the first column and row.
    if [ $edge = periodic ]; then
        "$PY" - "$T/t_periodic_cpu" <<'PYEOF' && ok || bad "periodic: the last tile's border is column/row 0"
import sys, numpy as np, tl
d = sys.argv[1]
assert np.array_equal(tl.tile(d, "f32", 3, 7)[:, -1], tl.tile(d, "f32", 3, 0)[:, 0])
assert np.array_equal(tl.tile(d, "f32", 7, 2)[-1, :], tl.tile(d, "f32", 0, 2)[0, :])
PYEOF
    fi
    "$BIN" tiles --levels 7 --tile 16 --hurst 0.6 --seed 77 --edge $edge --backend cpu -q --out "$T/one_$edge" &&
        ok || bad "$edge: one process"
    check 'diff -r "$T/one_$edge" "$T/t_${edge}_cpu" > /dev/null' "$edge: 3 processes make the same files as one"
    check 'diff -r "$T/t_${edge}_auto" "$T/t_${edge}_cpu" > /dev/null' \
        "$edge: the default backend and the CPU make the same bytes (tiles record no device)"
done
check '! diff -r "$T/one_ffc" "$T/one_periodic" > /dev/null' "ffc and periodic tiles differ"

# npy tiles, and a bigger tile, stitch too
"$BIN" tiles --levels 7 --tile 64 --hurst 0.6 --seed 77 --format npy --backend cpu -q --out "$T/npy" && ok || bad "npy tiles"
"$PY" - "$T/npy" "$T/whole_ffc.npy" <<'PYEOF' && ok || bad "npy tiles stitch into the whole grid"
import sys, numpy as np, tl
s, ix = tl.stitch(sys.argv[1], "npy")
assert ix["tiles_per_side"] == 2 and tl.bits_equal(s, np.load(sys.argv[2]))
PYEOF
"$BIN" tiles --levels 7 --tile 128 --hurst 0.6 --seed 77 --edge periodic --format npy --backend cpu -q --out "$T/npy1" &&
    "$PY" -c 'import sys, numpy as np, tl; a = np.load(sys.argv[1] + "/0/0.npy"); assert tl.bits_equal(a, tl.whole(sys.argv[2], True))' \
        "$T/npy1" "$T/whole_periodic.npy" && ok || bad "T = 2^N: one periodic tile, the whole torus plus its wrapped border"

# --noise: tiles of another distribution stitch into the whole grid of that distribution (two shares, two backends)
"$BIN" generate --levels 7 --hurst 0.6 --seed 77 --noise truncated:2 --backend cpu -q -o "$T/whole_tr.npy" &&
    "$BIN" tiles --levels 7 --tile 32 --hurst 0.6 --seed 77 --noise truncated:2 --format npy --backend cpu --only 0/2 -q --out "$T/tr" &&
    "$BIN" tiles --levels 7 --tile 32 --hurst 0.6 --seed 77 --noise truncated:2 --format npy --only 1/2 -q --out "$T/tr" 2> /dev/null &&
    ok || bad "truncated tiles"
"$PY" - "$T/tr" "$T/whole_tr.npy" "$T/whole_ffc.npy" <<'PYEOF' && ok || bad "--noise truncated:2 tiles stitch into that whole grid and are recorded"
import sys, numpy as np, tl
s, ix = tl.stitch(sys.argv[1], "npy")
assert tl.bits_equal(s, np.load(sys.argv[2])) and not tl.bits_equal(s, np.load(sys.argv[3]))
assert ix["parameters"]["noise"] == "truncated" and ix["parameters"]["noise_param"] == 2, ix["parameters"]
PYEOF

# ---- index.json ----
"$BIN" tiles --levels 9 --tile 128 --dimension 2.25 --sigma -3.5 --seed 18446744073709551615 --backend cpu --only 0/3 \
    -q --out "$T/ix_a" && ok || bad "index: share 0"
"$BIN" tiles --levels 9 --tile 128 --hurst 0.75 --sigma -3.5 --seed 0xffffffffffffffff --only 2/3 --out "$T/ix_b" \
    2> /dev/null && ok || bad "index: share 2 on the default backend"
check 'cmp -s "$T/ix_a/index.json" "$T/ix_b/index.json"' "index.json: the same bytes from every process and backend"
SPEC=$("$BIN" --version | sed -n 's/.*noise spec v\([0-9]*\).*/\1/p')
"$PY" - "$T/ix_a/index.json" "$SPEC" <<'PYEOF' && ok || bad "index.json content: $(cat "$T/ix_a/index.json")"
import json, sys
text = open(sys.argv[1]).read()
ix = json.loads(text)
want = {"format": "fracterra tiles", "format_version": 1, "layout": "grid", "spec_version": int(sys.argv[2]),
        "levels": 9, "edge": "ffc", "grid_side": 513, "tile": 128, "tile_samples": 129, "tiles_per_side": 4,
        "tile_count": 16, "path_template": "{row}/{col}.f32", "file_format": "f32"}
for k, v in want.items():
    assert ix[k] == v, (k, ix.get(k), v)
p = ix["parameters"]
assert p == {"hurst": 0.75, "dimension": 2.25, "sigma": -3.5, "seed": 18446744073709551615, "edge": "ffc", "noise": "gauss"}, p
assert "range" not in ix and "bits" not in ix            # lossless tiles have no range
assert "\"share" not in text and "\"only" not in text and "llvmpipe" not in text and "cpu" not in text
assert text.endswith("}\n")
PYEOF
"$BIN" tiles --levels 5 --tile 8 --edge periodic --backend cpu -q --out "$T/ix_p" &&
    "$PY" -c 'import json,sys; ix=json.load(open(sys.argv[1])); assert (ix["grid_side"], ix["tiles_per_side"], ix["tile_count"], ix["edge"], ix["parameters"]["seed"]) == (32, 4, 16, "periodic", 1), ix' \
        "$T/ix_p/index.json" && ok || bad "index.json of a periodic grid"

# ---- quantised tiles share one range ----
"$BIN" generate --levels 8 --seed 5 --hurst 0.3 --backend cpu -q -o "$T/w8.npy" && ok || bad "whole 8-level grid"
for fmt in png pgm; do
    "$BIN" tiles --levels 8 --tile 32 --seed 5 --hurst 0.3 --format $fmt --backend cpu -q --out "$T/q_$fmt" &&
        ok || bad "$fmt tiles"
    "$PY" - "$T/q_$fmt" "$T/w8.npy" $fmt <<'PYEOF' && ok || bad "$fmt tiles: shared derived range, exact quantisation, borders agree"
import sys, numpy as np, tl
d, w, fmt = sys.argv[1:]
s, ix = tl.stitch(d, fmt)
ref = np.load(w)
rg = ix["range"]
assert ix["bits"] == 16 and rg["source"] == "derived" and rg["from_levels"] == 8 and rg["margin"] == 0, rg
span = float(ref.max()) - float(ref.min())
# N <= 10: the range is the grid's min and max, rounded outward by at most 2^-19 of the span
assert rg["min"] <= ref.min() and rg["min"] >= ref.min() - span * 2.0**-19, (rg, ref.min())
assert rg["max"] >= ref.max() and rg["max"] <= ref.max() + span * 2.0**-19, (rg, ref.max())
assert np.array_equal(s, tl.quantise(ref, rg["min"], rg["max"], 65535))   # every tile on the one shared scale
assert s.min() <= 1 and s.max() >= 65534                                     # and the range is tight
for r in range(8):   # every tile records the shared range (PNG text chunks, PGM comment)
    for c in range(8):
        p = "%s/%d/%d.%s" % (d, r, c, fmt)
        if fmt == "png":
            t = tl.png(p)[1]; lo, hi = float(t["fracterra:min"]), float(t["fracterra:max"])
        else:
            line = [x for x in tl.pgm(p)[1] if "min=" in x][0]
            kv = dict(w.split("=", 1) for w in line.split() if "=" in w); lo, hi = float(kv["min"]), float(kv["max"])
        assert np.float32(lo) == np.float32(rg["min"]) and np.float32(hi) == np.float32(rg["max"]), (p, lo, hi, rg)
PYEOF
done
"$BIN" tiles --levels 8 --tile 64 --seed 5 --hurst 0.3 --format png --bits 8 --range -4,4.5 --backend cpu -q \
    --out "$T/q_given" && ok || bad "--range and --bits 8"
"$PY" - "$T/q_given" "$T/w8.npy" <<'PYEOF' && ok || bad "--range -4,4.5 --bits 8: recorded and used"
import sys, numpy as np, tl
s, ix = tl.stitch(sys.argv[1], "png")
assert ix["bits"] == 8 and ix["range"]["min"] == -4 and ix["range"]["max"] == 4.5 and ix["range"]["source"] == "given"
assert tl.png(sys.argv[1] + "/0/0.png")[2] == 8
assert np.array_equal(s, tl.quantise(np.load(sys.argv[2]), -4, 4.5, 255))
PYEOF
# N > 10: the range comes from the 10-level grid, widened; the whole 12-level grid lies inside it
"$BIN" generate --levels 12 --seed 9 --hurst 0.3 --backend cpu -q -o "$T/w12.npy" && ok || bad "whole 12-level grid"
"$BIN" tiles --levels 12 --tile 1024 --seed 9 --hurst 0.3 --format png --backend cpu -q --only 0/16 --out "$T/q12" &&
    ok || bad "12-level png tile"
"$PY" - "$T/q12" "$T/w12.npy" <<'PYEOF' && ok || bad "derived range at N = 12 holds the whole grid"
import json, sys, numpy as np, tl
ix = json.load(open(sys.argv[1] + "/index.json")); rg = ix["range"]; w = np.load(sys.argv[2])
assert rg["from_levels"] == 10 and rg["margin"] > 0, rg
assert rg["min"] < w.min() and w.max() < rg["max"], (rg, w.min(), w.max())
assert rg["max"] - rg["min"] < 3 * (float(w.max()) - float(w.min())), rg      # widened, not absurdly
assert np.array_equal(tl.png(sys.argv[1] + "/0/0.png")[0], tl.quantise(w[:1025, :1025], rg["min"], rg["max"], 65535))
PYEOF

# ---- a 24-level virtual grid: a few tiles, and exact agreement with the 7-level grid ----
# 2^24 / 64 = 262144 tiles a side, 2^36 tiles: share 5 of 10^10 makes 7 of them.
"$BIN" tiles --levels 24 --tile 64 --hurst 0.6 --seed 77 --only 5/10000000000 --out "$T/big" 2> "$T/err" &&
    ok || bad "N = 24: $(cat "$T/err")"
check '[ "$(find "$T/big" -name "*.f32" | wc -l)" = 7 ] && [ -s "$T/big/0/5.f32" ] && [ "$(stat -c %s "$T/big/0/5.f32")" = $((65 * 65 * 4)) ]' \
    "N = 24: 7 tiles of 65 x 65: $(find "$T/big" | head)"
check 'grep -Eq "\"tile_count\": ?68719476736" "$T/big/index.json" && grep -Eq "\"grid_side\": ?16777217" "$T/big/index.json"' \
    "N = 24: index counts 2^36 tiles of a 16777217-sample grid"
# With T = 1 and K = the tile count, share I is exactly tile I: tile (r, c) holds grid point (c, r), which for
# r, c multiples of 2^17 is point (c, r) / 2^17 of the 7-level grid (resolution independence).
for edge in ffc periodic; do for backend in cpu auto; do
    "$PY" - "$BIN" "$T/pts_${edge}_$backend" "$T/whole_$edge.npy" $edge $backend <<'PYEOF' && ok || bad "N = 24 $edge $backend tiles agree with the 7-level grid"
import subprocess, sys, numpy as np, tl
bin, d, w, edge, backend = sys.argv[1:]
g = tl.whole(w, edge == "periodic")
per = 1 << 24
for (i, j) in [(0, 0), (5, 3), (127, 64), (100, 127)]:
    r, c = j << 17, i << 17
    subprocess.run([bin, "tiles", "--levels", "24", "--tile", "1", "--hurst", "0.6", "--seed", "77", "--edge", edge,
                    "--backend", backend, "-q", "--out", d, "--only", "%d/%d" % (r * per + c, per * per)], check=True)
    a = tl.tile(d, "f32", r, c)
    assert a.shape == (2, 2) and a[0, 0].view(np.uint32) == g[j, i].view(np.uint32), (i, j, a, g[j, i])
    # the far corner of the last tile: point (2^24, 2^24), i.e. (128, 128) of the 7-level grid
r = c = per - 1
subprocess.run([bin, "tiles", "--levels", "24", "--tile", "1", "--hurst", "0.6", "--seed", "77", "--edge", edge, "--backend",
                backend, "-q", "--out", d, "--only", "%d/%d" % (r * per + c, per * per)], check=True)
assert tl.tile(d, "f32", r, c)[1, 1].view(np.uint32) == g[128, 128].view(np.uint32)
PYEOF
done; done

# --only with K near 2^64: share I is tile I alone, and no index arithmetic wraps around
K=18446744073709551615
"$BIN" tiles --levels 6 --tile 8 --backend cpu -q --only 13/$K --out "$T/hugek" &&
    check '[ "$(cd "$T/hugek" && find . -name "*.f32" | sort | tr "\n" " ")" = "./1/5.f32 " ]' \
        "--only 13/(2^64-1): tile 13 alone: $(cd "$T/hugek" && find . -name '*.f32')" || bad "--only 13/(2^64-1)"
"$BIN" tiles --levels 6 --tile 8 --backend cpu -q --only 18446744073709551614/$K --out "$T/hugek0" &&
    check '[ -s "$T/hugek0/index.json" ] && [ "$(ls "$T/hugek0")" = index.json ]' "--only beyond the last tile: no tile" ||
    bad "--only (2^64-2)/(2^64-1)"
"$BIN" tiles --levels 6 --tile 8 --backend cpu -q --pyramid --only 3/$K --out "$T/hugekp" &&
    check '[ "$(cd "$T/hugekp" && find . -name "*.png")" = ./1/0/1.png ]' \
        "pyramid --only 3/(2^64-1): zoom 1, x 0, y 1: $(cd "$T/hugekp" && find . -name '*.png')" || bad "pyramid --only 3/(2^64-1)"

# ---- XYZ pyramid ----
# N = 9, T = 32: zooms 0..4, zoom z the grid of 5 + z levels, 2^z x 2^z tiles of 32 x 32.
for edge in ffc periodic; do
    "$BIN" generate --levels 9 --seed 3 --edge $edge --backend cpu -q -o "$T/w9_$edge.npy" && ok || bad "whole 9-level grid"
    shares "$T/pyr_$edge" --levels 9 --tile 32 --seed 3 --edge $edge --pyramid && ok || bad "pyramid $edge: $(cat "$T/err")"
    "$BIN" tiles --levels 9 --tile 32 --seed 3 --edge $edge --pyramid --backend cpu -q --out "$T/pyr1_$edge" &&
        ok || bad "pyramid $edge, one process"
    check 'diff -r "$T/pyr_$edge" "$T/pyr1_$edge" > /dev/null' "pyramid $edge: 3 processes make the same files as one"
    "$PY" - "$T/pyr_$edge" "$T/w9_$edge.npy" <<'PYEOF' && ok || bad "pyramid $edge: levels are exact subsamples"
import json, os, sys, numpy as np, tl
d, w = sys.argv[1:]
ix = json.load(open(d + "/index.json"))
assert (ix["layout"], ix["min_zoom"], ix["max_zoom"], ix["tile"], ix["tile_samples"]) == ("xyz", 0, 4, 32, 32), ix
assert ix["url_template"] == "{z}/{x}/{y}.png" and ix["tile_count"] == 1 + 4 + 16 + 64 + 256, ix
assert [z["levels"] for z in ix["zooms"]] == [5, 6, 7, 8, 9] and [z["tiles_per_side"] for z in ix["zooms"]] == [1, 2, 4, 8, 16]
rg = ix["range"]
zooms = []
for z in range(5):
    n = 1 << z
    assert sorted(os.listdir("%s/%d" % (d, z)), key=int) == [str(x) for x in range(n)], z
    s = np.zeros((32 * n, 32 * n), np.uint16)
    for x in range(n):
        for y in range(n):
            a, text, bits = tl.png("%s/%d/%d/%d.png" % (d, z, x, y))   # z/x/y: x the column, y the row
            assert a.shape == (32, 32) and bits == 16
            s[32 * y:32 * y + 32, 32 * x:32 * x + 32] = a
    zooms.append(s)
for z in range(4):
    assert np.array_equal(zooms[z], zooms[z + 1][::2, ::2]), z                # zoom z = every other sample of z + 1
g = np.load(w)
assert np.array_equal(zooms[4], tl.quantise(g[:512, :512], rg["min"], rg["max"], 65535))
assert not np.array_equal(zooms[3], zooms[4][1::2, 1::2])                    # the check above can fail
PYEOF
done
"$BIN" tiles --levels 6 --tile 16 --pyramid --bits 8 --backend cpu -q --out "$T/pyr8" &&
    check '[ "$(od -An -tu1 -j24 -N1 "$T/pyr8/2/3/1.png" | tr -d " ")" = 8 ] && [ ! -e "$T/pyr8/3" ]' "pyramid --bits 8, zooms 0..2" ||
    bad "pyramid --bits 8"

# ---- progress ----
FRT_PROGRESS=always "$BIN" tiles --levels 6 --tile 8 --backend cpu --out "$T/prog" 2> "$T/err" && ok || bad "progress run"
check 'grep -q "64 tiles on" "$T/err" && grep -q "64 of 64 f32 tiles" "$T/err"' "progress and summary lines: $(cat "$T/err")"
FRT_PROGRESS=always "$BIN" tiles --levels 6 --tile 8 --backend cpu -q --out "$T/prog" 2> "$T/err" && ok || bad "quiet run"
check '[ ! -s "$T/err" ]' "--quiet silences progress and summary: $(cat "$T/err")"

"$BIN" tiles --levels 5 --tile 16 --backend cpu -q --out "$T/one_nodrv_ref" && ok || bad "5-level tiles on the CPU"

# ---- bad input: one line naming the problem, the exit code, nothing written ----
expect_fail() { # CODE WORD ARGS... : exit CODE, one line containing WORD, $T/out not created
    local code=$1 word=$2
    shift 2
    rm -rf "$T/out"
    "$BIN" tiles "$@" > "$T/out_stdout" 2> "$T/err"
    local rc=$? lines
    lines=$(wc -l < "$T/err")
    if [ "$rc" = "$code" ] && grep -qi -- "$word" "$T/err" && [ "$lines" = 1 ] && [ ! -e "$T/out" ]; then
        ok
    else
        bad "fracterra tiles $* -> rc $rc (want $code), $lines line(s): $(cat "$T/err"); out: $(ls -A "$T/out" 2>&1)"
    fi
}
O=(--out "$T/out")
expect_fail 2 levels --levels 0 --tile 4 "${O[@]}"
expect_fail 2 levels --levels 31 --tile 4 "${O[@]}"
expect_fail 2 levels --levels x --tile 4 "${O[@]}"
expect_fail 2 "missing --levels" --tile 4 "${O[@]}"
expect_fail 2 "--noise" --levels 6 --tile 4 --noise cauchy "${O[@]}"
expect_fail 2 "clt noise N" --levels 6 --tile 4 --noise clt:20 "${O[@]}"
expect_fail 2 "missing --out" --levels 5 --tile 4
expect_fail 2 "power of two" --levels 5 --tile 3 "${O[@]}"
expect_fail 2 "power of two" --levels 5 --tile 0 "${O[@]}"
expect_fail 2 "power of two" --levels 5 --tile -4 "${O[@]}"
expect_fail 2 "larger than the grid" --levels 5 --tile 64 "${O[@]}"
expect_fail 2 "larger than the grid" --levels 7 "${O[@]}" # the default tile, 256
expect_fail 2 "more than a file" --levels 20 --tile 65536 "${O[@]}"
expect_fail 2 only --levels 5 --tile 4 --only 3/3 "${O[@]}"
expect_fail 2 only --levels 5 --tile 4 --only 0/0 "${O[@]}"
expect_fail 2 only --levels 5 --tile 4 --only 1 "${O[@]}"
expect_fail 2 only --levels 5 --tile 4 --only -1/3 "${O[@]}"
expect_fail 2 only --levels 5 --tile 4 --only a/b "${O[@]}"
expect_fail 2 range --levels 5 --tile 4 --format png --range 5,1 "${O[@]}"
expect_fail 2 range --levels 5 --tile 4 --format png --range 1 "${O[@]}"
expect_fail 2 range --levels 5 --tile 4 --format png --range 0,nan "${O[@]}"
expect_fail 2 range --levels 5 --tile 4 --format png --range 1,1e39 "${O[@]}"
expect_fail 2 range --levels 5 --tile 4 --range 0,1 "${O[@]}"
expect_fail 2 bits --levels 5 --tile 4 --bits 8 "${O[@]}"
expect_fail 2 bits --levels 5 --tile 4 --format pgm --bits 12 "${O[@]}"
expect_fail 2 format --levels 5 --tile 4 --format tif "${O[@]}"
expect_fail 2 "PNG" --levels 5 --tile 4 --pyramid --format f32 "${O[@]}"
expect_fail 2 "pyramid" --levels 5 --tile 1 --pyramid "${O[@]}"
expect_fail 2 hurst --levels 5 --tile 4 --hurst 1 "${O[@]}"
expect_fail 2 "not both" --levels 5 --tile 4 --hurst 0.5 --dimension 2.5 "${O[@]}"
expect_fail 2 sigma --levels 5 --tile 4 --sigma 0 "${O[@]}"
expect_fail 2 seed --levels 5 --tile 4 --seed 18446744073709551616 "${O[@]}"
expect_fail 2 edge --levels 5 --tile 4 --edge wrap "${O[@]}"
expect_fail 2 backend --levels 5 --tile 4 --backend gpu "${O[@]}"
expect_fail 2 "unknown option" --levels 5 --tile 4 --tiles 4 "${O[@]}"
expect_fail 2 "unexpected argument" --levels 5 --tile 4 extra "${O[@]}"
expect_fail 4 "cannot create" --levels 5 --tile 4 --out "$T/missing/out"
touch "$T/out.file"
expect_fail 4 "not a directory" --levels 5 --tile 4 --out "$T/out.file"
check '[ -f "$T/out.file" ] && [ ! -s "$T/out.file" ]' "a file in the way is left alone"
expect_fail 3 "no-such-gpu" --levels 5 --tile 4 --device no-such-gpu "${O[@]}"
VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json \
    expect_fail 3 "mesa-vulkan-drivers" --levels 5 --tile 4 --backend vulkan "${O[@]}"
VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json \
    "$BIN" tiles --levels 5 --tile 16 --out "$T/nodrv" 2> "$T/err" && ok || bad "auto without a driver: $(cat "$T/err")"
check '[ "$(grep -c "warning: no usable Vulkan device" "$T/err")" = 1 ] && grep -q "using the CPU path" "$T/err" && diff -r "$T/nodrv" "$T/one_nodrv_ref" > /dev/null' \
    "auto without a driver: one warning, then the CPU makes the same files: $(cat "$T/err")"
if [ "$(id -u)" != 0 ]; then # root writes anywhere
    mkdir "$T/ro" && chmod 500 "$T/ro"
    expect_fail 4 "Permission denied" --levels 5 --tile 4 --out "$T/ro/out"
    expect_fail 4 "index.json" --levels 5 --tile 4 --out "$T/ro"
    check '[ -z "$(ls -A "$T/ro")" ]' "nothing written into a read-only directory"
fi
# An existing directory is kept, and a failure adds nothing to it.
mkdir -p "$T/keep" && echo old > "$T/keep/note"
"$BIN" tiles --levels 5 --tile 4 --device no-such-gpu --out "$T/keep" 2> /dev/null
check '[ "$(ls -A "$T/keep")" = note ]' "a failed run adds nothing to an existing directory: $(ls -A "$T/keep")"
"$BIN" tiles --levels 5 --tile 4 --backend cpu -q --out "$T/keep/" && [ -s "$T/keep/7/7.f32" ] && [ -s "$T/keep/index.json" ] &&
    [ "$(cat "$T/keep/note")" = old ] && ok || bad "an existing directory (given with a trailing slash) is filled"

echo "test_tiles: $pass passed, $fail failed"
[ "$fail" = 0 ]
