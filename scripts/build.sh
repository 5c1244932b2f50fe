#!/usr/bin/env bash
# build.sh — installs what is missing, then configures and builds the release preset into build/release.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release
