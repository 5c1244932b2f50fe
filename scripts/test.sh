#!/usr/bin/env bash
# test.sh — installs, builds and runs the whole test suite: the release build with the Vulkan validation layer
# required (any message fails), then the ASan + UBSan build, then a find_package consumer. .ci/run calls this.
set -uo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh || exit 1
passed=0 failed=0
log=$(mktemp)
trap 'rm -f "$log"' EXIT
for preset in release asan; do
  echo "== $preset: configure and build"
  cmake --preset "$preset" >/dev/null && cmake --build --preset "$preset" || { failed=$((failed + 1)); continue; }
  echo "== $preset: tests"
  ctest --preset "$preset" 2>&1 | tee "$log"
  line=$(grep -E 'tests passed, [0-9]+ tests? failed out of [0-9]+' "$log" | tail -1)
  if [ -z "$line" ]; then
    failed=$((failed + 1))
  else
    total=$(sed -E 's/.* out of ([0-9]+).*/\1/' <<<"$line")
    bad=$(sed -E 's/.*, ([0-9]+) tests? failed.*/\1/' <<<"$line")
    passed=$((passed + total - bad))
    failed=$((failed + bad))
  fi
done
echo "== fuzz: every file reader under libFuzzer + ASan/UBSan, ${FRT_FUZZ_SECONDS:-30} s from tests/fuzz_corpus"
if command -v clang >/dev/null; then
  corpus=$(mktemp -d)
  cp tests/fuzz_corpus/* "$corpus"/
  if cmake --preset fuzz >/dev/null && cmake --build --preset fuzz >/dev/null &&
    build/fuzz/tests/fuzz_read -max_total_time="${FRT_FUZZ_SECONDS:-30}" -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 "$corpus" 2>"$log"; then
    grep -E '^stat::number_of_executed_units|^Done' "$log" | tr '\n' ' '
    echo
    passed=$((passed + 1))
  else
    tail -40 "$log"
    failed=$((failed + 1))
  fi
  rm -rf "$corpus"
else
  echo "clang not installed: fuzzing skipped (the deterministic robustness pass in test_formats still ran)"
fi
echo "== consumer project: find_package(fracterra) from an install"
if scripts/check-install.sh; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
echo "all: $passed passed, $failed failed"
[ "$failed" = 0 ]
