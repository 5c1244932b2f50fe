#!/usr/bin/env bash
# install-deps.sh — installs what fracterra needs to build and test on Debian/Ubuntu (apt), if anything is missing.
# Runs as root, or through sudo. Safe to run again: it does nothing when everything is present.
set -euo pipefail
PACKAGES=(
  build-essential cmake git       # compiler and build
  libvulkan-dev                   # Vulkan loader and headers
  mesa-vulkan-drivers             # lavapipe: Vulkan on the CPU, so no GPU is needed
  glslang-tools                   # glslangValidator: GLSL -> SPIR-V at build time
  libpng-dev                      # PNG input and output
  libcairo2-dev                   # profile plots: anti-aliased PNG, SVG and PDF
  libgif-dev                      # giflib: animated GIF of the growth frames
  libjson-c-dev                   # json-c: the .f32 sidecar and other metadata (64-bit seeds exact)
  libgdal-dev                     # GDAL: GeoTIFF in and out (optional at build time: -DFRT_WITH_GDAL=OFF)
  pkg-config                      # finds cairo and json-c at configure time
  vulkan-validationlayers         # VK_LAYER_KHRONOS_validation for the tests
  vulkan-tools                    # vulkaninfo, for troubleshooting
  python3-numpy                   # independent .npy reader in the CLI test
)
# Optional: clang and its libFuzzer runtime for the fuzzing step of scripts/test.sh (skipped without them).
OPTIONAL=(clang libclang-rt-14-dev)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if command -v apt-cache >/dev/null; then
  for p in "${OPTIONAL[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" && continue
    apt-cache show "$p" >/dev/null 2>&1 && missing+=("$p")
  done
fi
[ ${#missing[@]} -eq 0 ] && exit 0
if ! command -v apt-get >/dev/null; then
  echo "install-deps.sh: no apt-get; install these yourself: ${missing[*]}" >&2
  exit 1
fi
SUDO=""
[ "$(id -u)" = 0 ] || SUDO=sudo
echo "install-deps.sh: installing ${missing[*]}" >&2
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
