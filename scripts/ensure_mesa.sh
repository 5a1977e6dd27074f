#!/usr/bin/env bash
# Install Mesa's software OpenGL (llvmpipe) when it is missing: the Blender tests and the demo
# render headless through EGL. Debian/Ubuntu only; prints what to do elsewhere.
set -euo pipefail
pkgs="libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1"
missing=""
for p in $pkgs; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
if ! command -v apt-get >/dev/null; then
    echo "Missing Mesa packages:$missing (install them with your package manager)" >&2
    exit 1
fi
sudo=""
[ "$(id -u)" -ne 0 ] && command -v sudo >/dev/null && sudo="sudo"
echo "Installing Mesa for headless OpenGL:$missing" >&2
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $missing >/dev/null
