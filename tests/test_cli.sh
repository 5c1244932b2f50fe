#!/usr/bin/env bash
# test_cli.sh — host/cli*.c: the `fracterra` command end to end: outputs, bad input, no driver, nothing clobbered.
# Usage: test_cli.sh PATH/TO/fracterra
set -u
BIN=$1
T=$(mktemp -d /tmp/frt_cli_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
check() { if eval "$1"; then ok; else bad "$2"; fi; }
PY=$(command -v /usr/bin/python3 || command -v python3 || true)
have_numpy() { [ -n "$PY" ] && "$PY" -c 'import numpy' 2>/dev/null; }
# Vulkan runs use the validation layer when installed; any message fails the test.
export FRT_VALIDATION=${FRT_CLI_VALIDATION:-1}

# ---- outputs ----
"$BIN" --version | grep -q '^fracterra [0-9]' && ok || bad "--version"
"$BIN" --help | grep -q 'generate' && ok || bad "--help"
"$BIN" generate --help | grep -q -- '--dimension' && ok || bad "generate --help"
"$BIN" devices --help >/dev/null && ok || bad "devices --help"
"$BIN" bench --help >/dev/null && ok || bad "bench --help"
"$BIN" devices > "$T/devices.txt" 2>&1 && grep -qi 'yes' "$T/devices.txt" && ok || bad "devices lists a usable device: $(cat "$T/devices.txt")"

"$BIN" generate --levels 7 --hurst 0.6 --seed 5 -o "$T/a.png" 2> "$T/err" && ok || bad "png: $(cat "$T/err")"
check '[ "$(head -c 8 "$T/a.png" | od -An -tx1 | tr -d " \n")" = 89504e470d0a1a0a ]' "PNG signature"
check '! grep -qi "validation" "$T/err"' "validation messages: $(cat "$T/err")"
check 'grep -q "129 x 129" "$T/err"' "summary line names the size"
"$BIN" generate --levels 7 --hurst 0.6 --seed 5 --backend vulkan -o "$T/v.npy" -q 2> "$T/err" && ok || bad "npy vulkan: $(cat "$T/err")"
check '[ ! -s "$T/err" ]' "--quiet prints nothing: $(cat "$T/err")"
"$BIN" generate --levels 7 --dimension 2.4 --seed 5 --backend cpu -o "$T/c.npy" -q && ok || bad "npy cpu"
"$BIN" generate --levels 7 --hurst 0.6 --seed 5 --backend cpu -o "$T/c6.npy" -q && ok || bad "npy cpu H"
"$BIN" generate --levels 5 --sigma -2 --seed 0x10 -o "$T/f.f32" -q && ok || bad "f32"
check '[ "$(stat -c %s "$T/f.f32")" = $((33 * 33 * 4)) ]' "f32 size"
check 'grep -Eq "\"width\": ?33" "$T/f.f32.json" && grep -Eq "\"seed\": ?16," "$T/f.f32.json" && grep -Eq "\"sigma\": ?-2," "$T/f.f32.json"' "sidecar: $(cat "$T/f.f32.json" 2>/dev/null)"
if have_numpy; then
    "$PY" - "$T" <<'PYEOF' && ok || bad "numpy checks"
import json, sys, numpy as np
t = sys.argv[1]
v = np.load(t + "/v.npy"); c = np.load(t + "/c6.npy")
assert v.shape == (129, 129) and v.dtype == np.float32, (v.shape, v.dtype)
assert np.abs(v - c).max() <= 1e-5, np.abs(v - c).max()          # vulkan vs cpu through the CLI
d = np.load(t + "/c.npy")
assert np.array_equal(d, c)                                          # --dimension 2.4 is --hurst 0.6
PYEOF
else
    echo "numpy not installed: skipping numpy.load checks"
fi

# ---- bad input: one message, non-zero exit, no file ----
expect_fail() { # CODE WORD ARGS... : exit CODE, message containing WORD, nothing written at $T/out.*
    local code=$1 word=$2
    shift 2
    rm -f "$T"/out.*
    "$BIN" "$@" > "$T/out_stdout" 2> "$T/err"
    local rc=$?
    local lines
    lines=$(wc -l < "$T/err")
    if [ "$rc" = "$code" ] && grep -qi -- "$word" "$T/err" && [ "$lines" = 1 ] && [ -z "$(ls "$T" | grep '^out\.')" ]; then
        ok
    else
        bad "fracterra $* -> rc $rc (want $code), $lines line(s): $(cat "$T/err")"
    fi
}
expect_fail 2 levels generate --levels 0 -o "$T/out.png"
expect_fail 2 levels generate --levels 16 -o "$T/out.png"
expect_fail 2 levels generate --levels ten -o "$T/out.png"
expect_fail 2 levels generate --levels 5x -o "$T/out.png"
expect_fail 2 hurst generate --hurst 1.5 -o "$T/out.png"
expect_fail 2 hurst generate --hurst 0 -o "$T/out.png"
expect_fail 2 hurst generate --hurst nan -o "$T/out.png"
expect_fail 2 dimension generate --dimension 3.5 -o "$T/out.png"
expect_fail 2 "not both" generate --hurst 0.5 --dimension 2.5 -o "$T/out.png"
expect_fail 2 sigma generate --sigma 0 -o "$T/out.png"
expect_fail 2 sigma generate --sigma inf -o "$T/out.png"
expect_fail 2 seed generate --seed -1 -o "$T/out.png"
expect_fail 2 seed generate --seed 18446744073709551616 -o "$T/out.png"
expect_fail 2 backend generate --backend gpu -o "$T/out.png"
expect_fail 2 "unknown option" generate --levles 5 -o "$T/out.png"
expect_fail 2 "needs a value" generate -o
expect_fail 2 "missing -o" generate --levels 5
expect_fail 2 ".xyz" generate --levels 5 -o "$T/out.xyz"
expect_fail 2 "no extension" generate --levels 5 -o "$T/out"
expect_fail 2 "unknown command" frobnicate
expect_fail 4 "No such file" generate --levels 5 -o "$T/missing-dir/out.png"
mkdir "$T/dir.png"
expect_fail 4 "directory" generate --levels 5 -o "$T/dir.png"
expect_fail 3 "no-such-gpu" generate --levels 5 --device no-such-gpu -o "$T/out.png"

# ---- no Vulkan driver ----
export VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json
expect_fail 3 "mesa-vulkan-drivers" generate --levels 5 --backend vulkan -o "$T/out.png"
"$BIN" generate --levels 5 -o "$T/auto.png" 2> "$T/err" && ok || bad "auto without driver: $(cat "$T/err")"
check 'grep -q "warning: no usable Vulkan device" "$T/err" && grep -q "using the CPU path" "$T/err" && [ -s "$T/auto.png" ]' "auto falls back with a warning: $(cat "$T/err")"
check '[ "$(grep -c warning "$T/err")" = 1 ]' "exactly one warning line"
unset VK_DRIVER_FILES VK_ICD_FILENAMES

# ---- nothing clobbered ----
printf 'old' > "$T/keep.png"
"$BIN" generate --levels 0 -o "$T/keep.png" 2>/dev/null
check '[ "$(cat "$T/keep.png")" = old ]' "bad arguments leave the old file"
VK_DRIVER_FILES=/nonexistent VK_ICD_FILENAMES=/nonexistent "$BIN" generate --levels 5 --backend vulkan -o "$T/keep.png" 2>/dev/null
check '[ "$(cat "$T/keep.png")" = old ]' "a failed generation leaves the old file"
check '[ -z "$(ls -a "$T" | grep tmp-)" ]' "no temporary files left: $(ls -a "$T")"
"$BIN" generate --levels 4 -q -o "$T/keep.png" && check '[ "$(head -c 4 "$T/keep.png" | tail -c 3)" = PNG ]' "success replaces it"

# ---- every format, several outputs in one run ----
"$BIN" generate --levels 6 --seed 9 --backend cpu -q -o "$T/m.pgm" -o "$T/m.obj" -o "$T/m.ply" -o "$T/m.npy" \
    -o "$T/m.f32" --spacing 2,3 --z-scale 10 && ok || bad "several outputs"
check '[ "$(head -c 2 "$T/m.pgm")" = P5 ] && head -c 600 "$T/m.pgm" | grep -q 65535' "PGM P5 16-bit header"
check '[ "$(grep -c "^v " "$T/m.obj")" = 4225 ] && [ "$(grep -c "^vn " "$T/m.obj")" = 4225 ] && [ "$(grep -c "^f " "$T/m.obj")" = 8192 ]' "OBJ: 65^2 vertices and normals, 2*64^2 faces"
head -c 4096 "$T/m.ply" | sed '/^end_header/q' > "$T/ply_header" 2>/dev/null
check 'grep -q "format binary_little_endian 1.0" "$T/ply_header" && grep -q "element vertex 4225" "$T/ply_header" && grep -q "element face 8192" "$T/ply_header"' "PLY header: $(head -c 300 "$T/ply_header")"
"$BIN" generate --levels 6 --seed 9 --backend cpu -q -o "$T/s.obj" --mesh-stride 4 && ok || bad "mesh stride"
check '[ "$(grep -c "^v " "$T/s.obj")" = 289 ] && [ "$(grep -c "^f " "$T/s.obj")" = 512 ]' "OBJ stride 4: 17^2 vertices, 2*16^2 faces"
"$BIN" generate --levels 6 --seed 9 --backend cpu -q -o "$T/b8.png" --bits 8 && ok || bad "--bits 8"
check '[ "$(od -An -tu1 -j24 -N1 "$T/b8.png" | tr -d " ")" = 8 ]' "8-bit PNG (IHDR bit depth)"
check 'grep -Eq "\"spacing_x\": ?2" "$T/m.f32.json" && grep -Eq "\"z_scale\": ?10" "$T/m.f32.json"' "sidecar records spacing and z-scale: $(cat "$T/m.f32.json" 2>/dev/null)"
if have_numpy; then
    "$PY" - "$T" <<'PYEOF' && ok || bad "numpy: formats agree"
import sys, numpy as np
t = sys.argv[1]
a = np.load(t + "/m.npy")
b = np.fromfile(t + "/m.f32", dtype="<f4").reshape(65, 65)
assert np.array_equal(a, b)
v = np.array([l.split()[1:] for l in open(t + "/m.obj") if l.startswith("v ")], dtype=np.float64)
assert np.allclose(v[:, 2].reshape(65, 65), 10 * a, rtol=1e-6, atol=1e-6)           # z = h * z_scale
assert v[1, 0] == 2 and v[0, 1] == 64 * 3 and v[-1, 1] == 0                          # x east, y north
PYEOF
fi

# ---- periodic edge ----
"$BIN" generate --levels 5 --edge periodic --seed 3 -q -o "$T/per.f32" && ok || bad "periodic"
check '[ "$(stat -c %s "$T/per.f32")" = $((32 * 32 * 4)) ] && grep -Eq "\"edge\": ?\"periodic\"" "$T/per.f32.json"' "periodic: 32 x 32, recorded in the sidecar"
"$BIN" generate --levels 5 --edge periodic --seed 3 -q --backend cpu -o "$T/per_cpu.f32" && cmp -s "$T/per.f32" "$T/per_cpu.f32" && ok || bad "periodic: the default backend and the CPU give the same bytes"
"$BIN" generate --levels 5 --edge periodic -q --frames "$T/per_frames" && [ "$(ls "$T/per_frames" | wc -l)" = 6 ] && ok || bad "periodic growth frames"
expect_fail 2 "edge" generate --levels 5 --edge wrap -o "$T/out.png"

# ---- render ----
"$BIN" render "$T/m.pgm" -o "$T/r_hs.png" 2> "$T/err" && ok || bad "render hillshade: $(cat "$T/err")"
check '[ "$(od -An -tu1 -j24 -N2 "$T/r_hs.png" | tr -s " ")" = " 8 0" ]' "hillshade: 8-bit grey"
"$BIN" render "$T/m.npy" --style color -q -o "$T/r_c.png" && ok || bad "render color"
check '[ "$(od -An -tu1 -j24 -N2 "$T/r_c.png" | tr -s " ")" = " 8 2" ]' "color: 8-bit RGB"
"$BIN" render "$T/m.f32" --style profiles --every 4 --base 5 -q -o "$T/r_p.svg" && ok || bad "render profiles svg"
check 'head -c 200 "$T/r_p.svg" | grep -q "<svg\|<?xml"' "SVG output"
"$BIN" render "$T/m.obj" --style profiles --dilation -0.5 -q -o "$T/r_p.pdf" && ok || bad "render profiles pdf from a mesh"
check '[ "$(head -c 4 "$T/r_p.pdf")" = %PDF ]' "PDF output"
"$BIN" render "$T/m.ply" --style profiles -q -o "$T/r_p.png" && ok || bad "render profiles png from a PLY"
"$BIN" render --help | grep -q -- '--dilation' && ok || bad "render --help"
expect_fail 4 "No such file" render "$T/none.png" -o "$T/out.png"
expect_fail 2 "profiles" render "$T/m.npy" -o "$T/out.svg"
expect_fail 2 "style" render "$T/m.npy" --style relief -o "$T/out.png"
expect_fail 2 "for --style profiles" render "$T/m.npy" --every 4 -o "$T/out.png"
expect_fail 2 "missing -o" render "$T/m.npy"
head -c 1000 "$T/m.npy" > "$T/trunc.npy"
expect_fail 4 "trunc.npy" render "$T/trunc.npy" -o "$T/out.png"
cp "$T/m.f32" "$T/w.f32" && sed 's/"width": *65/"width": 64/' "$T/m.f32.json" > "$T/w.f32.json"
expect_fail 2 "sidecar" render "$T/w.f32" -o "$T/out.png"
expect_fail 2 "bits" generate --levels 5 --bits 8 -o "$T/out.npy"
expect_fail 2 "bits" generate --levels 5 --bits 12 -o "$T/out.png"
expect_fail 2 "mesh-stride" generate --levels 5 --mesh-stride 0 -o "$T/out.obj"
expect_fail 2 "mesh-stride" generate --levels 5 --mesh-stride 2 -o "$T/out.png"
expect_fail 2 "gif" generate --levels 5 --gif "$T/out.png"
expect_fail 2 "twice" generate --levels 5 -o "$T/out.png" -o "$T/out.png"
expect_fail 2 "spacing" generate --levels 5 --spacing 0 -o "$T/out.png"
printf 'old' > "$T/keep_r.png"
"$BIN" render "$T/none.npy" -o "$T/keep_r.png" 2>/dev/null
check '[ "$(cat "$T/keep_r.png")" = old ]' "a failed render leaves the old file"
chmod 500 "$T/dir.png" 2>/dev/null
if [ "$(id -u)" != 0 ]; then
    expect_fail 4 "Permission denied" render "$T/m.npy" -o "$T/dir.png/out.png"
fi

# ---- preview, growth frames, GIF ----
"$BIN" generate --levels 7 --seed 3 -o "$T/g.png" --preview "$T/g_prev.png" --frames "$T/frames" --gif "$T/g.gif" \
    2> "$T/err" && ok || bad "preview + frames + gif: $(cat "$T/err")"
check '[ "$(ls "$T/frames" | grep -c "^frame-[0-9][0-9].png$")" = 8 ]' "frames: levels + 1 = 8 files: $(ls "$T/frames")"
check 'cmp -s "$T/frames/frame-07.png" "$T/g.png"' "the last frame is the final field, byte for byte"
check '! cmp -s "$T/frames/frame-06.png" "$T/g.png"' "frame 6 differs from the final field"
check '[ "$(head -c 6 "$T/g.gif")" = GIF89a ]' "GIF89a signature"
check '[ "$(od -An -tu1 -j24 -N2 "$T/g_prev.png" | tr -s " ")" = " 8 0" ]' "preview: 8-bit grey PNG"
if [ -n "$PY" ]; then
    "$PY" - "$T/g.gif" <<'PYEOF' && ok || bad "GIF has 8 frames, loops, 129 x 129"
import struct, sys
d = open(sys.argv[1], "rb").read()
w, h, flags = struct.unpack("<HHB", d[6:11])
assert (w, h) == (129, 129), (w, h)
i = 13 + (3 * 2 ** ((flags & 7) + 1) if flags & 0x80 else 0)
frames = loops = 0
while d[i] != 0x3B:
    if d[i] == 0x21:
        if d[i + 1] == 0xFF and d[i + 3:i + 14] == b"NETSCAPE2.0":
            loops += 1
        i += 2
        while d[i]:
            i += d[i] + 1
        i += 1
    elif d[i] == 0x2C:
        frames += 1
        fl = d[i + 9]
        i += 10 + (3 * 2 ** ((fl & 7) + 1) if fl & 0x80 else 0) + 1
        while d[i]:
            i += d[i] + 1
        i += 1
    else:
        raise SystemExit("bad block %#x at %d" % (d[i], i))
assert frames == 8 and loops == 1, (frames, loops)
PYEOF
fi
rm -rf "$T/frames2"
"$BIN" generate --levels 5 --frames "$T/frames2" -o "$T/out.xyz" 2>/dev/null
check '[ ! -e "$T/frames2" ]' "bad arguments create no frames directory"

# ---- progress ----
FRT_PROGRESS=always "$BIN" generate --levels 6 --backend cpu -o "$T/p.npy" 2> "$T/err" && ok || bad "progress run"
check 'grep -q "generating 65 x 65 on the CPU" "$T/err"' "FRT_PROGRESS=always shows the progress line: $(cat "$T/err")"
FRT_PROGRESS=always "$BIN" generate --levels 6 --backend cpu -q -o "$T/p.npy" 2> "$T/err" && ok || bad "quiet run"
check '[ ! -s "$T/err" ]' "--quiet silences progress too"

# ---- regions: a window of the grid, equal bit for bit to the same part of the whole grid ----
FFC_WINDOWS="10,20,40,30 0,0,17,5 240,250,17,7 0,256,257,1 0,0,257,257 256,0,1,257"    # corners, edges, whole
TORUS_WINDOWS="0,0,64,64 50,60,30,20 63,63,2,2 10,5,130,3 0,0,1,1"                      # wrapping, wider than the torus
for be in cpu auto; do
    "$BIN" generate --levels 8 --seed 4 --backend $be -q -o "$T/whole_$be.npy" && ok || bad "whole grid ($be)"
    "$BIN" generate --levels 6 --edge periodic --seed 4 --backend $be -q -o "$T/torus_$be.npy" && ok || bad "whole torus ($be)"
    for w in $FFC_WINDOWS; do
        "$BIN" generate --levels 8 --seed 4 --backend $be -q --region "$w" -o "$T/reg_${be}_$w.npy" 2> "$T/err" && ok || bad "region $w ($be): $(cat "$T/err")"
    done
    for w in $TORUS_WINDOWS; do
        "$BIN" generate --levels 6 --edge periodic --seed 4 --backend $be -q --region "$w" -o "$T/preg_${be}_$w.npy" 2> "$T/err" && ok || bad "periodic region $w ($be): $(cat "$T/err")"
    done
done
if have_numpy; then
    "$PY" - "$T" "$FFC_WINDOWS" "$TORUS_WINDOWS" <<'PYEOF' && ok || bad "numpy: every region equals its crop of the whole grid"
import sys, numpy as np
t, ffc, torus = sys.argv[1], sys.argv[2].split(), sys.argv[3].split()
for be in ("cpu", "auto"):
    whole = np.load(f"{t}/whole_{be}.npy")
    for w in ffc:
        x, y, wd, ht = map(int, w.split(","))
        r = np.load(f"{t}/reg_{be}_{w}.npy")
        assert r.shape == (ht, wd), (be, w, r.shape)
        assert np.array_equal(r, whole[y:y + ht, x:x + wd]), (be, w)
    tor = np.load(f"{t}/torus_{be}.npy")
    m = tor.shape[0]
    for w in torus:
        x, y, wd, ht = map(int, w.split(","))
        r = np.load(f"{t}/preg_{be}_{w}.npy")
        assert r.shape == (ht, wd), (be, w, r.shape)
        assert np.array_equal(r, tor[np.ix_((y + np.arange(ht)) % m, (x + np.arange(wd)) % m)]), (be, w)
PYEOF
else
    echo "numpy not installed: skipping the region crop checks"
fi
# A window of a 2^24+1 grid: every output, the preview and the summary are the window's; the metadata records it.
for be in cpu auto; do
    "$BIN" generate --levels 24 --region 1000000,2000000,64,48 --seed 7 --backend $be -o "$T/r24_$be.f32" \
        -o "$T/r24_$be.png" --preview "$T/r24_prev_$be.png" 2> "$T/err" && ok || bad "levels 24 region ($be): $(cat "$T/err")"
    check 'grep -q "64 x 48 at 1000000,2000000 of the 16777217 x 16777217 grid (levels 24" "$T/err"' "region summary line ($be): $(cat "$T/err")"
    check '[ "$(stat -c %s "$T/r24_$be.f32" 2>/dev/null)" = $((64 * 48 * 4)) ]' "levels 24 region ($be): 64 x 48 floats"
    check '[ "$(od -An -tu1 -j16 -N8 "$T/r24_$be.png" 2>/dev/null | tr -s " ")" = " 0 0 0 64 0 0 0 48" ] && [ "$(od -An -tu1 -j16 -N8 "$T/r24_prev_$be.png" 2>/dev/null | tr -s " ")" = " 0 0 0 64 0 0 0 48" ]' "levels 24 region ($be): PNG and preview are 64 x 48"
    check 'tr -d " \n" < "$T/r24_$be.f32.json" | grep -q "\"region\":{\"x\":1000000,\"y\":2000000,\"width\":64,\"height\":48},\"grid_side\":16777217"' "sidecar records the region: $(cat "$T/r24_$be.f32.json" 2>/dev/null)"
done
"$BIN" render "$T/r24_cpu.png" -q -o "$T/r24_render.png" && ok || bad "render reads a region's PNG"
if have_numpy; then
    "$PY" - "$T" <<'PYEOF' && ok || bad "numpy: levels 24 region finite, not flat, same on both backends"
import sys, numpy as np
t = sys.argv[1]
a = np.fromfile(t + "/r24_cpu.f32", dtype="<f4").reshape(48, 64)
b = np.fromfile(t + "/r24_auto.f32", dtype="<f4").reshape(48, 64)
assert np.isfinite(a).all() and a.std() > 0, a
assert np.array_equal(a, b)                       # spec v2: every backend gives the same bits
PYEOF
fi
"$BIN" generate --levels 30 --edge periodic --region 1073741800,5,64,64 --backend cpu -q -o "$T/r30.npy" && ok || bad "levels 30 periodic region wrapping the torus"
FRT_PROGRESS=always "$BIN" generate --levels 8 --region 10,20,40,30 --backend cpu -o "$T/p.npy" 2> "$T/err" && ok || bad "region progress run"
check 'grep -q "generating 40 x 30 at 10,20 of the 257 x 257 grid on the CPU" "$T/err"' "region progress line: $(cat "$T/err")"
# Bad regions: one line naming the problem (and the grid's side), exit 2, nothing written.
expect_fail 2 "X0,Y0,W,H" generate --region 1,2,3 -o "$T/out.png"
expect_fail 2 "X0,Y0,W,H" generate --region 1,2,3,4,5 -o "$T/out.png"
expect_fail 2 "X0,Y0,W,H" generate --region a,b,c,d -o "$T/out.png"
expect_fail 2 "X0,Y0,W,H" generate --region -1,0,4,4 -o "$T/out.png"
expect_fail 2 "X0,Y0,W,H" generate --region 1,,3,4 -o "$T/out.png"
expect_fail 2 "X0,Y0,W,H" generate --region "" -o "$T/out.png"
expect_fail 2 "X0,Y0,W,H" generate --region 0,0,4294967296,1 -o "$T/out.png"
expect_fail 2 "at least 1" generate --region 0,0,0,4 -o "$T/out.png"
expect_fail 2 "at least 1" generate --region 0,0,4,0 -o "$T/out.f32"
expect_fail 2 "at least 1" generate --region 0,0,0,0 -o "$T/out.png"
expect_fail 2 "65 x 65 grid" generate --levels 6 --region 60,0,10,10 -o "$T/out.png"
expect_fail 2 "65 x 65 grid" generate --levels 6 --region 0,0,66,1 -o "$T/out.f32"
expect_fail 2 "65 x 65 grid" generate --levels 6 --region 0,65,1,1 -o "$T/out.png"
expect_fail 2 "513 x 513 grid" generate --region 500,0,14,1 -o "$T/out.png"
expect_fail 2 "1073741825 x 1073741825 grid" generate --levels 30 --region 4294967295,0,1,1 -o "$T/out.png"
expect_fail 2 "64 x 64 periodic grid" generate --levels 6 --edge periodic --region 64,0,4,4 -o "$T/out.png"
expect_fail 2 "64 x 64 periodic grid" generate --levels 6 --edge periodic --region 0,64,4,4 -o "$T/out.png"
expect_fail 2 "2^32" generate --levels 30 --region 0,0,100000,100000 -o "$T/out.png"
expect_fail 2 "needs --region" generate --levels 20 -o "$T/out.png"
expect_fail 2 "levels" generate --levels 31 --region 0,0,1,1 -o "$T/out.png"
expect_fail 2 "--frames" generate --region 0,0,4,4 --frames "$T/out.frames" -o "$T/out.png"
expect_fail 2 "--gif" generate --region 0,0,4,4 --gif "$T/out.gif"

# ---- real data (ALGORITHM.md §3.4-3.6, §2.8): densify, estimates, maps, distributions, GeoTIFF ----
if have_numpy; then
    D="$T/dens"
    mkdir -p "$D"
    "$BIN" generate --levels 9 --hurst 0.7 --sigma 50 --seed 42 -o "$D/full.npy" -q && ok || bad "full field"
    "$PY" -c '
import sys, numpy as np
d = sys.argv[1]; a = np.load(d + "/full.npy")
c = a[::8, ::8].copy(); c[5:9, 20:30] = np.nan; c[0, 0] = np.nan; np.save(d + "/holes.npy", c)
np.save(d + "/bad100.npy", np.zeros((100, 100), np.float32)); np.save(d + "/rect.npy", np.zeros((65, 33), np.float32))
i = c.copy(); i[3, 3] = np.inf; np.save(d + "/inf.npy", i)
np.save(d + "/allnan.npy", np.full((65, 65), np.nan, np.float32))
h = np.zeros((2, 64), np.float32); h[:, :32] = 0.3; h[:, 32:] = 0.9; np.save(d + "/hmap.npy", h)
np.save(d + "/dmap.npy", np.array([[2.5, 2.25], [2.75, 2.5]], np.float32))
np.save(d + "/dmap_h.npy", np.array([[0.5, 0.75], [0.25, 0.5]], np.float32))
np.save(d + "/amap.npy", np.array([[1, 3], [0.5, -1]], np.float32))
np.save(d + "/hbad.npy", np.array([[0.5, 1.5], [0.5, 0.5]], np.float32))
np.save(d + "/thin.npy", np.full((1, 5), 0.5, np.float32))
' "$D" && ok || bad "numpy inputs"
    # a coarse grid cut from a field, with holes, densifies back to exactly that field, on both backends
    for be in auto cpu; do
        "$BIN" generate --levels 9 --hurst 0.7 --sigma 50 --seed 42 --coarse "$D/holes.npy" --backend $be -o "$D/back_$be.npy" -o "$D/back_$be.f32" -q 2> "$T/err" && ok || bad "densify $be: $(cat "$T/err")"
    done
    "$PY" -c '
import sys, numpy as np
d = sys.argv[1]; a = np.load(d + "/full.npy")
for be in ("auto", "cpu"):
    b = np.load(d + "/back_%s.npy" % be)
    assert np.array_equal(a.view(np.uint32), b.view(np.uint32)), be
' "$D" && ok || bad "densifying every 8th point (with holes) of a field gives back the field bit for bit"
    check 'grep -Eq "\"coarse_levels\": ?6" "$D/back_cpu.f32.json" && grep -q "densified from .*holes.npy (65 x 65, k = 6, 4184 known, 41 no-data)" "$D/back_cpu.f32.json"' "sidecar records the densify: $(cat "$D/back_cpu.f32.json")"
    # known samples are kept bit for bit from every input format (as the library reads them)
    "$BIN" generate --levels 6 --sigma 20 --seed 3 -o "$D/k.png" -o "$D/k.pgm" -o "$D/k.f32" -o "$D/k.npy" -o "$D/k.tif" -q && ok || bad "coarse in every format"
    for ext in png pgm f32 npy tif; do
        "$BIN" generate --levels 6 --coarse "$D/k.$ext" -o "$D/same_$ext.npy" -q 2> "$T/err" &&
            "$BIN" generate --levels 8 --coarse "$D/k.$ext" --seed 9 -o "$D/up_$ext.npy" -q 2>> "$T/err" && ok || bad "densify from .$ext: $(cat "$T/err")"
        "$PY" -c '
import sys, numpy as np
d, ext = sys.argv[1], sys.argv[2]
s = np.load(d + "/same_%s.npy" % ext); u = np.load(d + "/up_%s.npy" % ext)
assert s.shape == (65, 65) and u.shape == (257, 257)
assert np.array_equal(u[::4, ::4].view(np.uint32), s.view(np.uint32))
if ext in ("f32", "npy", "tif"):
    assert np.array_equal(s.view(np.uint32), np.load(d + "/k.npy").view(np.uint32))
' "$D" $ext && ok || bad "known samples of .$ext kept bit for bit"
    done
    # --fit pad: a 50 x 40 grid (cut from the field, plus 2000) is mirrored out to 65 x 65; the output is the data's
    # area, 393 x 313, its known samples kept bit for bit, the same on both backends
    "$PY" -c '
import sys, numpy as np
d = sys.argv[1]; a = np.load(d + "/full.npy")
np.save(d + "/c5040.npy", a[::8, ::8][:40, :50] + np.float32(2000))
np.save(d + "/c65.npy", a[::8, ::8])
' "$D" && ok || bad "--fit pad inputs"
    for be in auto cpu; do
        "$BIN" generate --levels 9 --coarse "$D/c5040.npy" --fit pad --hurst 0.7 --sigma 50 --backend $be -o "$D/fit_$be.npy" -o "$D/fit_$be.f32" -q 2> "$T/err" && ok || bad "--fit pad $be: $(cat "$T/err")"
    done
    "$BIN" generate --levels 9 --coarse "$D/c5040.npy" --fit pad --hurst 0.7 --sigma 50 --region 100,40,64,200 -o "$D/fit_r.npy" -q 2> "$T/err" && ok || bad "--fit pad --region: $(cat "$T/err")"
    "$PY" -c '
import sys, numpy as np
d = sys.argv[1]
o, c = np.load(d + "/fit_auto.npy"), np.load(d + "/c5040.npy")
assert o.shape == (313, 393), o.shape                                      # (w-1)*8+1 x (h-1)*8+1
assert np.array_equal(o.view(np.uint32), np.load(d + "/fit_cpu.npy").view(np.uint32)), "vulkan != cpu"
assert np.array_equal(o[::8, ::8].view(np.uint32), c.view(np.uint32)), "known samples changed"
assert np.array_equal(o[40:240, 100:164].view(np.uint32), np.load(d + "/fit_r.npy").view(np.uint32)), "region != crop"
# No edge artefact: the output minus the field the data was cut from (its detail differs: another seed) is as
# large along the last column and row as inside. Mirror padding measures |mean| / RMS 0.11 and 0.22 and RMS ratios
# 0.97 and 0.99 (column, row); NaN padding, filled by the contract from corners near 0, gives 5.0 and 9.3, 6.0 and
# 10.3, so bounds of 0.5 and 1.5 separate them.
diff = o.astype(np.float64) - (np.load(d + "/full.npy")[:313, :393] + 2000)
rms = np.sqrt(np.mean(diff ** 2))
for edge in (diff[:, -1], diff[-1, :]):
    assert abs(edge.mean()) <= 0.5 * rms and np.sqrt(np.mean(edge ** 2)) <= 1.5 * rms, (edge.mean(), edge.std(), rms)
' "$D" && ok || bad "--fit pad: shape, known samples, backends, region, no edge artefact"
    check 'grep -q "densified from .*c5040.npy (50 x 40, mirrored to 65 x 65 by --fit pad, k = 6, 2000 known, 0 no-data)" "$D/fit_cpu.f32.json" && grep -Eq "\"width\": ?393" "$D/fit_cpu.f32.json"' "--fit pad recorded: $(cat "$D/fit_cpu.f32.json")"
    "$BIN" generate --levels 8 --coarse "$D/c65.npy" -o "$D/c65a.npy" -q && "$BIN" generate --levels 8 --coarse "$D/c65.npy" --fit pad -o "$D/c65b.npy" -q && cmp -s "$D/c65a.npy" "$D/c65b.npy" && ok || bad "--fit pad on a 2^k+1 grid changes nothing"
    "$BIN" generate --levels 5 --region 0,0,30,20 --sigma 300 --crs EPSG:32633 --origin 500000,4600000 --spacing 30 -o "$D/geo_r.tif" -q 2> "$T/err" &&
        "$BIN" generate --levels 8 --coarse "$D/geo_r.tif" --fit pad -o "$D/geo_r8.tif" -o "$D/geo_r8.npy" -q 2>> "$T/err" && ok || bad "--fit pad of a GeoTIFF: $(cat "$T/err")"
    "$PY" -c 'import sys, numpy as np; assert np.load(sys.argv[1] + "/geo_r8.npy").shape == (153, 233)' "$D" && ok || bad "--fit pad GeoTIFF: 30 x 20 at k = 5 -> 233 x 153"
    expect_fail 2 "pad" generate --levels 9 --coarse "$D/c5040.npy" --fit resample -o "$T/out.npy"
    expect_fail 2 "--coarse" generate --levels 9 --fit pad -o "$T/out.npy"
    expect_fail 2 "ffc" generate --levels 9 --edge periodic --coarse "$D/c5040.npy" --fit pad -o "$T/out.npy"
    expect_fail 2 "data's area" generate --levels 9 --coarse "$D/c5040.npy" --fit pad --region 0,300,10,20 -o "$T/out.npy"
    expect_fail 2 "--fit pad" generate --levels 9 --coarse "$D/c5040.npy" --fit pad --gif "$T/out.gif"
    expect_fail 2 "2 x 2" generate --levels 9 --coarse "$D/thin.npy" --fit pad -o "$T/out.npy"
    # --hurst auto --sigma auto: printed, recorded, close to the truth (129^2 coarse: test_estimate bounds)
    "$BIN" generate --levels 10 --hurst 0.6 --sigma 80 --seed 7 -o "$D/f10.npy" -q
    "$PY" -c 'import sys, numpy as np; d = sys.argv[1]; np.save(d + "/c129.npy", np.load(d + "/f10.npy")[::8, ::8])' "$D"
    "$BIN" generate --levels 10 --coarse "$D/c129.npy" --hurst auto --sigma auto --seed 8 -o "$D/auto.f32" 2> "$T/err" && ok || bad "auto: $(cat "$T/err")"
    check 'grep -q "estimated from .*c129.npy (7 levels" "$T/err"' "estimates printed: $(cat "$T/err")"
    "$PY" -c '
import json, sys
m = json.load(open(sys.argv[1] + "/auto.f32.json"))
assert abs(m["hurst"] - 0.6) <= 0.1 and abs(m["sigma"] / 80 - 1) <= 0.2, m
assert "hurst and sigma estimated" in m["history"], m["history"]
' "$D" && ok || bad "estimates within H 0.1, sigma 20%, in the sidecar: $(cat "$D/auto.f32.json")"
    "$BIN" generate --levels 10 --coarse "$D/c129.npy" --hurst 0.5 --sigma auto -o "$D/auto2.f32" 2> "$T/err" && grep -q "H (given) 0.5" "$T/err" && ok || bad "sigma auto with a given H: $(cat "$T/err")"
    # maps: a dimension map equals the roughness map of H = 3 - D (exact values); both backends agree
    "$BIN" generate --levels 8 --dimension-map "$D/dmap.npy" --amplitude-map "$D/amap.npy" -o "$D/dm.npy" -q 2> "$T/err" && ok || bad "dimension map: $(cat "$T/err")"
    "$BIN" generate --levels 8 --roughness-map "$D/dmap_h.npy" --amplitude-map "$D/amap.npy" --backend cpu -o "$D/rm.npy" -o "$D/rm.f32" -q 2> "$T/err" && ok || bad "roughness map: $(cat "$T/err")"
    "$PY" -c 'import sys, numpy as np; d = sys.argv[1]; assert np.array_equal(np.load(d + "/dm.npy").view(np.uint32), np.load(d + "/rm.npy").view(np.uint32))' "$D" && ok || bad "dimension map = roughness map of 3 - D, vulkan = cpu"
    check 'grep -q "roughness map .*dmap_h.npy (2 x 2); amplitude map .*amap.npy (2 x 2)" "$D/rm.f32.json"' "maps recorded: $(cat "$D/rm.f32.json")"
    "$BIN" generate --levels 10 --roughness-map "$D/hmap.npy" --backend cpu -o "$D/halves.npy" -q && ok || bad "halves map"
    "$PY" -c '
import sys, numpy as np
h = np.load(sys.argv[1] + "/halves.npy").astype(np.float64)
def rough(a):  # RMS of the finest square-step residuals along rows
    return np.sqrt(np.mean((a[:, 1:-1:2] - 0.5 * (a[:, 0:-2:2] + a[:, 2::2])) ** 2))
l, r = rough(h[:, 64:448]), rough(h[:, 576:960])
assert l > 5 * r, (l, r)   # H 0.3 vs 0.9 at level 10: amplitude ratio 2^(-10*0.3)/2^(-10*0.9) = 64 (less the mean noise)
' "$D" && ok || bad "roughness map: the rough half is rougher at the finest level"
    # distributions: recorded, and the same bits on both backends
    for nz in truncated:2 clt:4 uniform; do
        "$BIN" generate --levels 8 --noise $nz -o "$D/nz.npy" -o "$D/nz.f32" -q 2> "$T/err" &&
            "$BIN" generate --levels 8 --noise $nz --backend cpu -o "$D/nzc.npy" -q 2>> "$T/err" && ok || bad "--noise $nz: $(cat "$T/err")"
        "$PY" -c 'import sys, numpy as np; d = sys.argv[1]; assert np.array_equal(np.load(d + "/nz.npy").view(np.uint32), np.load(d + "/nzc.npy").view(np.uint32))' "$D" && ok || bad "--noise $nz: vulkan = cpu"
        check 'grep -Eq "\"noise\": ?\"${nz%%:*}\"" "$D/nz.f32.json"' "--noise $nz recorded: $(cat "$D/nz.f32.json")"
    done
    "$BIN" generate --levels 8 --noise gauss -o "$D/g1.npy" -q && "$BIN" generate --levels 8 -o "$D/g2.npy" -q && cmp -s "$D/g1.npy" "$D/g2.npy" && ok || bad "--noise gauss is the default"
    # GeoTIFF: a georeferenced coarse grid gives an output with the same CRS, pixels 2^(N-k) smaller, same centres
    "$BIN" generate --levels 5 --sigma 300 --crs EPSG:32633 --origin 500000,4600000 --spacing 30 -o "$D/geo.tif" -q 2> "$T/err" && ok || bad "georeferenced .tif: $(cat "$T/err")"
    "$BIN" generate --levels 8 --coarse "$D/geo.tif" --hurst auto --sigma auto -o "$D/geo8.tif" -q 2> "$T/err" && ok || bad "densify a GeoTIFF: $(cat "$T/err")"
    "$PY" - "$D" <<'PYEOF' && ok || bad "GeoTIFF georeferencing of the densified output"
import struct, sys
def tags(path):   # the first IFD's ModelPixelScale (33550), ModelTiepoint (33922) and GeoKeyDirectory (34735)
    b = open(path, "rb").read()
    e = "<" if b[:2] == b"II" else ">"
    big = struct.unpack(e + "H", b[2:4])[0] == 43
    if big:
        off = struct.unpack(e + "Q", b[8:16])[0]; n = struct.unpack(e + "Q", b[off:off + 8])[0]; p = off + 8; esz = 20
    else:
        off = struct.unpack(e + "I", b[4:8])[0]; n = struct.unpack(e + "H", b[off:off + 2])[0]; p = off + 2; esz = 12
    out = {}
    for k in range(n):
        ent = b[p + k * esz:p + (k + 1) * esz]
        tag, typ = struct.unpack(e + "HH", ent[:4])
        cnt, val = (struct.unpack(e + "Q", ent[4:12])[0], ent[12:20]) if big else (struct.unpack(e + "I", ent[4:8])[0], ent[8:12])
        size = {3: 2, 12: 8}.get(typ, 1) * cnt
        data = val[:size] if size <= len(val) else b[struct.unpack(e + ("Q" if big else "I"), val)[0]:][:size]
        fmt = {3: "H", 12: "d"}.get(typ)
        if fmt:
            out[tag] = struct.unpack(e + fmt * cnt, data)
    return out
d = sys.argv[1]
a, b = tags(d + "/geo.tif"), tags(d + "/geo8.tif")
sa, sb = a[33550], b[33550]
assert abs(sa[0] - 30) < 1e-9 and abs(sb[0] - 30 / 8) < 1e-9 and abs(sb[1] - 30 / 8) < 1e-9, (sa, sb)
ta, tb = a[33922], b[33922]    # (i, j, k, X, Y, Z) of the corner of pixel (0, 0)
ca = (ta[3] + sa[0] / 2, ta[4] - sa[1] / 2); cb = (tb[3] + sb[0] / 2, tb[4] - sb[1] / 2)
assert abs(ca[0] - 500000) < 1e-6 and abs(ca[1] - 4600000) < 1e-6, ca     # --origin is the top-left centre
assert abs(cb[0] - ca[0]) < 1e-6 and abs(cb[1] - ca[1]) < 1e-6, (ca, cb)  # same centre after densifying
assert 32633 in b[34735], b[34735]                                           # EPSG:32633 kept
a, b = tags(d + "/geo_r.tif"), tags(d + "/geo_r8.tif")                       # --fit pad: the same, for a 30 x 20
ca = (a[33922][3] + a[33550][0] / 2, a[33922][4] - a[33550][1] / 2); cb = (b[33922][3] + b[33550][0] / 2, b[33922][4] - b[33550][1] / 2)
assert abs(b[33550][0] - 30 / 8) < 1e-9 and abs(ca[0] - 500000) < 1e-6 and abs(cb[0] - ca[0]) < 1e-6 and abs(cb[1] - ca[1]) < 1e-6, (ca, cb)
assert 32633 in b[34735], b[34735]
PYEOF
    # bad inputs: one line, exit 2 (4 for a missing file), no output
    expect_fail 2 "2^k" generate --levels 9 --coarse "$D/bad100.npy" -o "$T/out.npy"
    expect_fail 2 "square" generate --levels 9 --coarse "$D/rect.npy" -o "$T/out.npy"
    expect_fail 2 "infinite" generate --levels 9 --coarse "$D/inf.npy" -o "$T/out.npy"
    expect_fail 2 "no known height" generate --levels 9 --coarse "$D/allnan.npy" -o "$T/out.npy"
    expect_fail 2 "at least 6" generate --levels 5 --coarse "$D/holes.npy" -o "$T/out.npy"
    expect_fail 2 "needs --levels" generate --coarse "$D/holes.npy" -o "$T/out.npy"
    expect_fail 4 "coarse" generate --levels 9 --coarse "$D/missing.npy" -o "$T/out.npy"
    expect_fail 2 "needs --coarse" generate --levels 9 --hurst auto -o "$T/out.npy"
    expect_fail 2 "needs --coarse" generate --levels 9 --sigma auto -o "$T/out.npy"
    expect_fail 2 "(0, 1)" generate --levels 6 --roughness-map "$D/hbad.npy" -o "$T/out.npy"
    expect_fail 2 "(2, 3)" generate --levels 6 --dimension-map "$D/dmap_h.npy" -o "$T/out.npy"
    expect_fail 2 "2 x 2" generate --levels 6 --amplitude-map "$D/thin.npy" -o "$T/out.npy"
    expect_fail 2 "not with --hurst" generate --levels 6 --hurst 0.5 --roughness-map "$D/hmap.npy" -o "$T/out.npy"
    expect_fail 2 "one of" generate --levels 6 --roughness-map "$D/hmap.npy" --dimension-map "$D/dmap.npy" -o "$T/out.npy"
    expect_fail 2 "--noise" generate --levels 6 --noise cauchy -o "$T/out.npy"
    expect_fail 2 "noise" generate --levels 6 --noise truncated:0.5 -o "$T/out.npy"
    expect_fail 2 "noise" generate --levels 6 --noise clt:2.5 -o "$T/out.npy"
    expect_fail 2 "--noise" generate --levels 6 --noise uniform:3 -o "$T/out.npy"
    expect_fail 2 "--crs" generate --levels 6 --crs EPSG:4326 -o "$T/out.npy"
    expect_fail 2 "georeferenced" generate --levels 8 --coarse "$D/geo.tif" --origin 1,2 -o "$T/out.tif"
    expect_fail 2 "CRS" generate --levels 6 --crs EPSG:999999 -o "$T/out.tif"
else
    echo "numpy not installed: skipping the densify checks"
fi

# ---- the manual names every option of every command ----
MAN=$(dirname "$0")/../docs/fracterra.1
for cmd in generate render devices bench; do
    for opt in $("$BIN" $cmd --help | grep -oE -- '--[a-z][a-z0-9-]+' | sort -u); do
        grep -q -- "$(printf '%s' "$opt" | sed 's/-/\\\\-/g')" "$MAN" && ok || bad "docs/fracterra.1 lacks $cmd $opt"
    done
done

# ---- bench ----
"$BIN" bench --levels 4-5 --runs 2 --json > "$T/bench.json" 2> "$T/err" && ok || bad "bench: $(cat "$T/err")"
if [ -n "$PY" ]; then
    "$PY" -c 'import json,sys; d=json.load(open(sys.argv[1])); r=d["results"]; assert len(r)==4 and all(x["points_per_s_total"]>0 for x in r), r' "$T/bench.json" && ok || bad "bench JSON: $(cat "$T/bench.json")"
fi
expect_fail 2 runs bench --runs 0
"$BIN" bench --region --window 16 --levels 8,24 --runs 1 --json > "$T/bench_region.json" 2> "$T/err" && ok || bad "bench --region: $(cat "$T/err")"
if [ -n "$PY" ]; then
    "$PY" -c 'import json,sys; d=json.load(open(sys.argv[1])); r=d["results"]; assert d["mode"]=="region" and len(r)==4 and all(x["width"]==16 and x["height"]==16 and x["side"] in (257, 16777217) and x["points_per_s_total"]>0 for x in r), r' "$T/bench_region.json" && ok || bad "bench --region JSON: $(cat "$T/bench_region.json")"
fi
"$BIN" bench --region --window 16x8 --levels 12 --runs 1 --backend cpu > "$T/bench_region.txt" 2> "$T/err" && ok || bad "bench --region table: $(cat "$T/err")"
check 'grep -q "16 x 8 window centred" "$T/bench_region.txt" && grep -Eq "^cpu .* 12 +4097 " "$T/bench_region.txt"' "bench --region table: $(cat "$T/bench_region.txt")"
expect_fail 2 "window" bench --window 16
expect_fail 2 "does not fit" bench --region --window 100 --levels 5
expect_fail 2 "levels" bench --levels 20
expect_fail 2 "levels" bench --region --levels 24,20

echo "test_cli: $pass passed, $fail failed"
[ "$fail" = 0 ]
