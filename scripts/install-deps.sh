#!/usr/bin/env bash
# install-deps.sh — installs what fracterra needs to build and test on Debian/Ubuntu (apt), if anything is missing.
# Runs as root, or through sudo. Safe to run again: it does nothing when everything is present.
set -euo pipefail
PACKAGES=(
  build-essential cmake git       # compiler and build
  libvulkan-dev                   # Vulkan loader and headers
  mesa-vulkan-drivers             # lavapipe: Vulkan on the CPU, so no GPU is needed
  glslang-tools                   # glslangValidator: GLSL -> SPIR-V at build time
  libpng-dev                      # PNG output
  vulkan-validationlayers         # VK_LAYER_KHRONOS_validation for the tests
  vulkan-tools                    # vulkaninfo, for troubleshooting
  python3-numpy                   # independent .npy reader in the CLI test
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
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
