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
check 'grep -q "\"width\": 33" "$T/f.f32.json" && grep -q "\"seed\": 16," "$T/f.f32.json" && grep -q "\"sigma\": -2," "$T/f.f32.json"' "sidecar: $(cat "$T/f.f32.json" 2>/dev/null)"
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
expect_fail 2 ".tif" generate --levels 5 -o "$T/out.tif"
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

# ---- bench ----
"$BIN" bench --levels 4-5 --runs 2 --json > "$T/bench.json" 2> "$T/err" && ok || bad "bench: $(cat "$T/err")"
if [ -n "$PY" ]; then
    "$PY" -c 'import json,sys; d=json.load(open(sys.argv[1])); r=d["results"]; assert len(r)==4 and all(x["points_per_s_total"]>0 for x in r), r' "$T/bench.json" && ok || bad "bench JSON: $(cat "$T/bench.json")"
fi
expect_fail 2 runs bench --runs 0

echo "test_cli: $pass passed, $fail failed"
[ "$fail" = 0 ]
