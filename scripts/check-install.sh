#!/usr/bin/env bash
# check-install.sh — installs the release build into a temporary prefix and builds examples/consumer against it
# with find_package(fracterra), then runs it.
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install build/release --prefix "$tmp/prefix" >/dev/null
cmake -S examples/consumer -B "$tmp/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/build" >/dev/null
"$tmp/build/consumer"
