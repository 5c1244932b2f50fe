#!/usr/bin/env bash
# test_info.sh — host/cli_info.c: `fracterra info FILE [--json] [--stats]` end to end: the text and JSON of every
# format fracterra writes, the recorded parameters (seed exact, region and grid side, noise), a foreign GeoTIFF's
# geotransform, projection and nodata, --stats against numpy, and bad input failing with one line and exit 2 or 4.
# Usage: test_info.sh PATH/TO/fracterra   (needs /usr/bin/python3 with numpy; skips, exit 77, without)
set -u
BIN=$1
T=$(mktemp -d /tmp/frt_info_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
PY=/usr/bin/python3
if ! "$PY" -c 'import numpy' 2>/dev/null; then
    echo "test_info: /usr/bin/python3 with numpy is needed; skipped"
    exit 77
fi
export FRT_PROGRESS=never

# info FILE ARGS...: stdout to $T/out, stderr to $T/err; fails the check when it does not exit 0 or prints on stderr.
info() {
    local f=$1
    shift
    "$BIN" info "$f" "$@" > "$T/out" 2> "$T/err"
    local rc=$?
    if [ "$rc" = 0 ] && [ ! -s "$T/err" ]; then
        ok
        return 0
    fi
    bad "info $f $*: rc $rc, stderr: $(cat "$T/err")"
    return 1
}
# has KEY VALUE: the text output in $T/out has the line "KEY:<spaces>VALUE", the value starting in column 15.
has() {
    if grep -qxF -- "$(printf '%-14s%s' "$1:" "$2")" "$T/out"; then
        ok
    else
        bad "$CTX: no line '$1: $2' in: $(cat "$T/out")"
    fi
}
# lacks KEY: no line for KEY in $T/out.
lacks() {
    if grep -q -- "^$1:" "$T/out"; then bad "$CTX: unexpected line $(grep -- "^$1:" "$T/out")"; else ok; fi
}
# pyjson 'ASSERTIONS' : runs Python with d = the JSON object in $T/out (which must be exactly one JSON document).
pyjson() {
    if "$PY" -c 'import json, sys, math
d = json.load(open(sys.argv[1]))
exec(sys.argv[2])' "$T/out" "$1" 2> "$T/pyerr"; then
        ok
    else
        bad "$CTX JSON: $(tail -n 2 "$T/pyerr" | tr "\n" " ") in: $(head -c 600 "$T/out")"
    fi
}
# expect_fail CODE WORD ARGS... : exit CODE, nothing on stdout, one line on stderr naming WORD, starting with the
# command's prefix.
expect_fail() {
    local code=$1 word=$2
    shift 2
    "$BIN" info "$@" > "$T/fout" 2> "$T/ferr"
    local rc=$?
    local lines
    lines=$(wc -l < "$T/ferr")
    if [ "$rc" = "$code" ] && [ "$lines" = 1 ] && grep -q '^fracterra info: ' "$T/ferr" &&
        grep -qF -- "$word" "$T/ferr" && [ ! -s "$T/fout" ]; then
        ok
    else
        bad "info $* -> rc $rc (want $code), $lines line(s) (want 1, naming '$word'): $(cat "$T/ferr")"
    fi
}

# ---- help, dispatch, and the manual ----
"$BIN" info --help > "$T/help" 2>&1 && grep -q -- '--stats' "$T/help" && grep -q -- '--json' "$T/help" && ok ||
    bad "info --help: $(cat "$T/help")"
"$BIN" --help | grep -q '^  fracterra info FILE' && ok || bad "fracterra --help does not list info"
MAN=$(dirname "$0")/../docs/fracterra.1
grep -q '^\.SS info$' "$MAN" && ok || bad "docs/fracterra.1 has no info section"
nopt=0
for opt in $("$BIN" info --help | grep -oE -- '--[a-z][a-z0-9-]+' | sort -u); do
    nopt=$((nopt + 1))
    # the man page's part from ".SS info" to the next section must name the option (dashes escaped: \-)
    sed -n '/^\.SS info$/,/^\.S[SH] [^i]/p' "$MAN" | grep -q -- "$(printf '%s' "$opt" | sed 's/-/\\\\-/g')" && ok ||
        bad "the info section of docs/fracterra.1 lacks $opt"
done
[ "$nopt" -ge 3 ] && ok || bad "info --help names $nopt options, expected --json, --stats, --help"
# every JSON key is documented in the manual's info section, in bold (\fBkey\fR)
for key in file format width height bits recorded_range spacing_x spacing_y z_scale backend device terrain levels \
    hurst dimension sigma seed edge region grid_side noise noise_param geotransform projection nodata stats min max \
    mean stddev valid_count nan_count inf_count; do
    sed -n '/^\.SS info$/,/^\.S[SH] [^i]/p' "$MAN" | grep -qF -- "\\fB$key\\fR" && ok ||
        bad "the info section of docs/fracterra.1 does not name the JSON key $key"
done

# ---- every format fracterra writes: text and JSON ----
SEED=12345678901234567890 # above 2^63: must survive exactly (not through a double)
GEN=(--levels 5 --hurst 0.7 --sigma 2.5 --seed "$SEED" --spacing 2,3 --z-scale 4 --backend cpu -q)
formats="png pgm f32 npy obj ply"
if "$BIN" generate "${GEN[@]}" -o "$T/t.tif" 2> "$T/err"; then
    formats="$formats tif"
elif grep -qi 'gdal' "$T/err"; then
    echo "test_info: built without GDAL, .tif not checked ($(cat "$T/err"))"
else
    bad "generate -o t.tif: $(cat "$T/err")"
fi
for e in $formats; do
    [ "$e" = tif ] || "$BIN" generate "${GEN[@]}" -o "$T/t.$e" 2> "$T/err" || bad "generate -o t.$e: $(cat "$T/err")"
done
for e in $formats; do
    CTX="info t.$e"
    info "$T/t.$e" || continue
    case $e in png | pgm) bits=16 ;; *) bits=32 ;; esac
    has file "$T/t.$e"
    has format "$e"
    has size "33 x 33"
    has bits "$bits"
    if [ "$e" = npy ]; then # .npy holds the array only
        has spacing "1 x 1"
        has z_scale 1
        has parameters "none recorded"
        lacks backend
        lacks levels
    else
        has spacing "2 x 3"
        has z_scale 4
        has backend cpu
        has levels 5
        has hurst 0.7
        has dimension 2.3
        has sigma 2.5
        has seed "$SEED"
        has edge ffc
        has noise gauss
        lacks parameters
    fi
    lacks region
    lacks noise_param
    lacks min
    if [ "$e" = tif ]; then
        has geotransform "-1 2 0 97.5 0 -3" # north up, pixel centres on the mesh vertices (frt_write_desc)
        has projection none
        has nodata none
    else
        lacks geotransform
    fi
    [ "$(grep -c . "$T/out")" = "$(grep -cE '^[a-z_]+: +[^ ]' "$T/out")" ] && ok ||
        bad "$CTX: a line is not 'key: value'"
    info "$T/t.$e" --json || continue
    pyjson "
keys = ['file', 'format', 'width', 'height', 'bits', 'recorded_range', 'spacing_x', 'spacing_y', 'z_scale', 'backend',
        'device', 'terrain', 'geotransform', 'projection', 'nodata', 'stats']
assert list(d) == keys, list(d)
assert d['file'] == '$T/t.$e' and d['format'] == '$e' and d['width'] == 33 and d['height'] == 33, d
assert d['bits'] == $bits and d['recorded_range'] is ('$e' in ('png', 'pgm')), d
if '$e' == 'npy':  # the array only: nothing recorded
    assert (d['spacing_x'], d['spacing_y'], d['z_scale']) == (1, 1, 1), d
    assert d['backend'] is None and d['device'] is None and d['terrain'] is None, d
else:
    assert (d['spacing_x'], d['spacing_y'], d['z_scale']) == (2, 3, 4), d
    assert d['backend'] == 'cpu' and isinstance(d['device'], str) and d['device'], d
    t = d['terrain']
    assert list(t) == ['levels', 'hurst', 'dimension', 'sigma', 'seed', 'edge', 'region', 'grid_side', 'noise',
                       'noise_param'], list(t)
    assert t == dict(levels=5, hurst=0.7, dimension=2.3, sigma=2.5, seed=$SEED, edge='ffc', region=None,
                     grid_side=33, noise='gauss', noise_param=None), t
assert d['stats'] is None and d['projection'] is None and d['nodata'] is None, d
assert d['geotransform'] == ([-1, 2, 0, 97.5, 0, -3] if '$e' == 'tif' else None), d['geotransform']
"
done

# ---- --stats against numpy's figures of the .npy, for every format ----
# Float formats hold the same float32 heights, so min and max are equal and mean and stddev agree within 1e-10
# relative: double sums of 1089 floats differ from numpy's pairwise sums by about n * 2^-53 = 1.2e-13 relative.
# PNG and PGM store 16-bit quanta: every height is within half a quantum q = (max - min) / 65535 of the original, so
# min, max and mean lie within q/2, and the stddev within q/2 too (|std(x + e) - std(x)| <= std(e) <= max |e|).
for e in $formats; do
    CTX="info t.$e --stats"
    info "$T/t.$e" --stats --json || continue
    pyjson "
import numpy as np
h = np.load('$T/t.npy').astype(np.float64)
s = d['stats']
assert list(s) == ['min', 'max', 'mean', 'stddev', 'valid_count', 'nan_count', 'inf_count'], list(s)
assert (s['valid_count'], s['nan_count'], s['inf_count']) == (h.size, 0, 0), s
want = dict(min=h.min(), max=h.max(), mean=h.mean(), stddev=h.std())
if '$e' in ('png', 'pgm'):
    tol = 0.5 * (h.max() - h.min()) / 65535 * (1 + 1e-6)   # half a quantum, plus float32 rounding of the result
    for k in want: assert abs(s[k] - want[k]) <= tol, (k, s[k], want[k], tol)
else:
    # min and max are float32 heights written as the shortest decimal that reads back as the same float32
    assert np.float32(s['min']) == np.float32(want['min']) and np.float32(s['max']) == np.float32(want['max']), s
    for k in ('mean', 'stddev'): assert abs(s[k] - want[k]) <= 1e-10 * abs(want[k]), (k, s[k], want[k])
"
    info "$T/t.$e" --stats || continue
    # the text shows the same figures
    "$PY" -c 'import json, sys
d = json.load(open(sys.argv[1]))["stats"]
for k in ("min", "max", "mean", "stddev"): print("%-14s%r" % (k + ":", d[k]))' <("$BIN" info "$T/t.$e" --stats --json) > "$T/want"
    while read -r k v; do has "${k%:}" "$v"; done < "$T/want"
    has nan_count 0
    lacks inf_count
done

# ---- NaN (no-data) and infinite cells; a foreign file records no parameters ----
"$PY" -c 'import numpy as np, sys
h = np.arange(24, dtype=np.float32).reshape(4, 6) - 5.5
h[0, 0] = h[2, 3] = h[3, 5] = np.nan
h[1, 1] = np.inf
np.save(sys.argv[1], h)' "$T/nan.npy"
CTX="info nan.npy --stats"
if info "$T/nan.npy" --stats --json; then
    pyjson "
import numpy as np
h = np.load('$T/nan.npy').astype(np.float64)
f = h[np.isfinite(h)]
s = d['stats']
assert (s['valid_count'], s['nan_count'], s['inf_count']) == (20, 3, 1), s
assert np.float32(s['min']) == f.min() and np.float32(s['max']) == f.max(), s
assert abs(s['mean'] - f.mean()) <= 1e-12 and abs(s['stddev'] - f.std()) <= 1e-12, (s, f.mean(), f.std())
assert d['terrain'] is None and d['backend'] is None and d['device'] is None and d['recorded_range'] is False, d
assert (d['width'], d['height'], d['bits'], d['spacing_x'], d['z_scale']) == (6, 4, 32, 1, 1), d
"
fi
if info "$T/nan.npy" --stats; then
    has size "6 x 4"
    has parameters "none recorded"
    has nan_count 3
    has inf_count 1
    lacks levels
    lacks backend
fi
"$PY" -c 'import numpy as np, sys; np.save(sys.argv[1], np.full((3, 2), np.nan, np.float32))' "$T/allnan.npy"
CTX="info allnan.npy --stats"
if info "$T/allnan.npy" --stats --json; then
    pyjson "
s = d['stats']
assert s == dict(min=None, max=None, mean=None, stddev=None, valid_count=0, nan_count=6, inf_count=0), s
"
fi

# ---- regions and noise parameters ----
CTX="info region ffc"
"$BIN" generate --levels 8 --region 3,5,16,8 --noise truncated:2.5 --backend cpu -q -o "$T/r.png" ||
    bad "generate --region"
if info "$T/r.png"; then
    has size "16 x 8"
    has levels 8
    has region "3,5,16,8"
    has grid_side 257
    has noise truncated
    has noise_param 2.5
fi
if info "$T/r.png" --json; then
    pyjson "
t = d['terrain']
assert t['region'] == dict(x=3, y=5, width=16, height=8) and list(t['region']) == ['x', 'y', 'width', 'height'], t
assert t['grid_side'] == 257 and t['levels'] == 8 and t['noise'] == 'truncated' and t['noise_param'] == 2.5, t
assert (d['width'], d['height']) == (16, 8), d
"
fi
# periodic: the window wraps around the 64 x 64 torus; the grid's side is 2^N
CTX="info region periodic"
"$BIN" generate --levels 6 --edge periodic --region 60,62,10,4 --noise clt --backend cpu -q -o "$T/p.f32" ||
    bad "generate --edge periodic --region"
if info "$T/p.f32"; then
    has edge periodic
    has region "60,62,10,4"
    has grid_side 64
    has noise clt
    has noise_param 4 # the default N, made explicit
fi
if info "$T/p.f32" --json; then
    pyjson "
t = d['terrain']
assert t['region'] == dict(x=60, y=62, width=10, height=4) and t['grid_side'] == 64 and t['edge'] == 'periodic', t
assert t['noise'] == 'clt' and t['noise_param'] == 4, t
"
fi

# ---- a foreign GeoTIFF: UTM 33N, 10 m pixels, nodata -9999 (written here byte by byte: no GDAL tools needed) ----
if [ "${formats%tif}" != "$formats" ]; then
    "$PY" - "$T/geo.tif" <<'PYEOF'
import struct, sys
import numpy as np
w, h = 5, 4
px = (np.arange(w * h, dtype=np.float32) * 1.5 + 100).reshape(h, w)
px[1, 2] = px[3, 0] = -9999.0                                    # two no-data cells
ascii_nodata = b"-9999\0"
geokeys = [1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, 32633]   # projected, pixel is area, EPSG:32633
scale = struct.pack("<3d", 10.0, 10.0, 0.0)
tie = struct.pack("<6d", 0, 0, 0, 500000.0, 4000000.0, 0)
entries = [  # (tag, type, count, value or bytes): types 3 SHORT, 4 LONG, 12 DOUBLE, 2 ASCII
    (256, 4, 1, w), (257, 4, 1, h), (258, 3, 1, 32), (259, 3, 1, 1), (262, 3, 1, 1), (273, 4, 1, None),
    (277, 3, 1, 1), (278, 4, 1, h), (279, 4, 1, w * h * 4), (284, 3, 1, 1), (339, 3, 1, 3),
    (33550, 12, 3, scale), (33922, 12, 6, tie), (34735, 3, len(geokeys), struct.pack("<%dH" % len(geokeys), *geokeys)),
    (42113, 2, len(ascii_nodata), ascii_nodata)]
ifd_size = 2 + 12 * len(entries) + 4
extra, extra_at = b"", 8 + ifd_size
offsets = {}
for tag, typ, n, v in entries:
    if isinstance(v, bytes) and len(v) > 4:
        offsets[tag] = extra_at + len(extra); extra += v + (b"\0" if len(v) % 2 else b"")
data_at = extra_at + len(extra)
ifd = struct.pack("<H", len(entries))
for tag, typ, n, v in entries:
    if tag == 273: v = data_at
    if tag in offsets: field = struct.pack("<I", offsets[tag])
    elif isinstance(v, bytes): field = v.ljust(4, b"\0")
    elif typ == 3: field = struct.pack("<HH", v, 0)
    else: field = struct.pack("<I", v)
    ifd += struct.pack("<HHI", tag, typ, n) + field
ifd += struct.pack("<I", 0)
open(sys.argv[1], "wb").write(b"II*\0" + struct.pack("<I", 8) + ifd + extra + px.astype("<f4").tobytes())
PYEOF
    CTX="info geo.tif"
    if info "$T/geo.tif" --stats; then
        has format tif
        has size "5 x 4"
        has bits 32
        has spacing "10 x 10" # a north-up projected raster: its pixel size
        has geotransform "500000 10 0 4000000 0 -10"
        has projection "WGS 84 / UTM zone 33N (EPSG:32633)"
        has nodata -9999
        has parameters "none recorded"
        has nan_count 2
        has min 100
        has max 128.5
    fi
    if info "$T/geo.tif" --json --stats; then
        pyjson "
import numpy as np
assert d['geotransform'] == [500000, 10, 0, 4000000, 0, -10] and d['nodata'] == -9999, d
p = d['projection']
assert p.startswith(('PROJCS[\"WGS 84 / UTM zone 33N\"', 'PROJCRS[\"WGS 84 / UTM zone 33N\"')) and '32633' in p, p
assert len(p) > 200 and p.count('[') == p.count(']'), 'the whole WKT, not a short form'
v = np.arange(20, dtype=np.float64) * 1.5 + 100
v = np.delete(v, [1 * 5 + 2, 3 * 5 + 0])
s = d['stats']
assert (s['valid_count'], s['nan_count']) == (18, 2) and np.float32(s['min']) == v.min() and s['max'] == v.max(), s
assert abs(s['mean'] - v.mean()) <= 1e-12 * v.mean() and abs(s['stddev'] - v.std()) <= 1e-12 * v.mean(), s
assert d['terrain'] is None and d['spacing_x'] == 10 and d['spacing_y'] == 10, d
"
    fi
fi

# ---- bad input: one line naming the file, exit 2 (malformed) or 4 (I/O), nothing on stdout ----
expect_fail 4 "$T/none.png" "$T/none.png"
expect_fail 4 "$T/none.png" "$T/none.png" --stats --json
mkdir -p "$T/dir.png"
expect_fail 4 "$T/dir.png" "$T/dir.png"
printf 'not a png at all, just text\n' > "$T/bad.png"
expect_fail 2 "$T/bad.png" "$T/bad.png"
printf '\x93NUMPY\x01\x00\x10\x00{bad header    }\n' > "$T/bad.npy"
expect_fail 2 "$T/bad.npy" "$T/bad.npy" --json
cp "$T/t.f32" "$T/nosidecar.f32"
expect_fail 4 "$T/nosidecar.f32" "$T/nosidecar.f32"
printf 'P5\n33 33\n65535\n' > "$T/short.pgm" # a header promising 33 x 33 samples, and none
expect_fail 4 "$T/short.pgm" "$T/short.pgm" --stats
head -c 200 "$T/t.npy" > "$T/cut.npy" # the header whole, the data cut
expect_fail 4 "$T/cut.npy" "$T/cut.npy" --stats
cp "$T/t.npy" "$T/t.xyz"
expect_fail 2 "$T/t.xyz" "$T/t.xyz"
printf 'v 0 0 0\nv 1 0\n' > "$T/bad.obj"
expect_fail 2 "$T/bad.obj" "$T/bad.obj"
expect_fail 2 "missing the heightfield file"
expect_fail 2 "missing" --json
expect_fail 2 "unexpected argument" "$T/t.npy" "$T/t.png"
expect_fail 2 "--bogus" "$T/t.npy" --bogus
expect_fail 2 "'--stats' takes no value" "$T/t.npy" --stats=3
# the command failing on bad input prints nothing on stdout; the same reading succeeds on the good file
info "$T/t.npy" --stats --json >/dev/null

echo "test_info: $pass passed, $fail failed"
[ "$fail" = 0 ]
