#!/usr/bin/env bash
# Run tests in a real Blender 5.1 / 5.2 (the bpy module on CPython 3.13 and NumPy 2), which this
# machine's Python (3.11) cannot load.
#
#   scripts/blender_next.sh BPY_VERSION [PYTEST ARGUMENTS...]
#   scripts/blender_next.sh BPY_VERSION --python [PYTHON ARGUMENTS...]   (e.g. scripts/demo.py)
#
# A Debian 13 root, made once with debootstrap from the Debian archive apt already uses, has
# CPython 3.13; each bpy version gets a virtualenv in it (the add-on's requirements and the test
# requirements beside it), made once and remade when a requirements file changes. The tests run
# in that root with this checkout bind-mounted at /src. Every mount lives in a private mount
# namespace (unshare), so it goes away with the run however the run ends: nothing is left
# mounted on the host, and the root can always be deleted. The root lives under
# $VOODOO_NEXT_CACHE (default /var/cache/voodoo-next); delete that folder to start over.
# Needs root (debootstrap, chroot and mount do).
set -euo pipefail

fail() { echo "blender_next: $*" >&2; exit 1; }

[ $# -ge 1 ] || fail "usage: scripts/blender_next.sh BPY_VERSION [--python] [ARGUMENTS...]"
version=$1
shift
checkout=$(cd "$(dirname "$0")/.." && pwd)
cache=${VOODOO_NEXT_CACHE:-/var/cache/voodoo-next}
suite=trixie
# CPython 3.13 and, for bpy to load headless, Mesa's EGL/GL and the X libraries bpy links to.
packages=python3,python3-venv,ca-certificates,libegl1,libegl-mesa0,libgl1-mesa-dri,libgbm1,libgl1
packages=$packages,libxrender1,libxi6,libxxf86vm1,libxfixes3,libxkbcommon0,libsm6,libice6
rootfs=$cache/$suite
venv=/opt/bpy-$version

[ "$(id -u)" -eq 0 ] || fail "needs root: debootstrap, chroot and mount make and enter the
Debian 13 root that runs Blender $version. Run 'make test' as root (CI does)."
for tool in unshare chroot mount; do
    command -v $tool >/dev/null || fail "'$tool' is missing (Debian package util-linux)"
done

mkdir -p "$cache"
exec 9>"$cache/lock"
flock 9  # one run at a time makes or changes the root

mirror() {
    # The Debian archive apt already uses (deb822 or one-line sources), else Debian's own.
    local uri
    uri=${VOODOO_DEBIAN_MIRROR:-$(cat /etc/apt/sources.list.d/*.sources 2>/dev/null \
        | awk '/^URIs:/ && $2 !~ /security/ {print $2; exit}')}
    uri=${uri:-$(cat /etc/apt/sources.list 2>/dev/null \
        | awk '/^deb / && $2 !~ /security/ {print $2; exit}')}
    echo "${uri:-http://deb.debian.org/debian}"
}

make_root() {
    local stamp
    stamp=$rootfs/.voodoo-root-$(echo "$suite $packages" | cksum | cut -d' ' -f1)
    [ -e "$stamp" ] && return 0
    if grep -q " $cache/" /proc/mounts; then
        fail "something is still mounted under $cache (an old run from before this script?):
$(grep " $cache/" /proc/mounts | cut -d' ' -f2)
unmount it (umount -R PATH), then run again"
    fi
    "$checkout/scripts/ensure_debs.sh" debootstrap
    local url log=$cache/debootstrap.log
    url=$(mirror)
    echo "Making a Debian 13 ($suite) root with CPython 3.13 from $url (once; about a minute)" >&2
    rm -rf "$rootfs" "$rootfs.partial"
    if ! debootstrap --variant=minbase --include="$packages" "$suite" "$rootfs.partial" "$url" \
        >"$log" 2>&1; then
        tail -n 20 "$log" >&2
        fail "debootstrap could not make the Debian 13 root from $url (log: $log);
set VOODOO_DEBIAN_MIRROR to a reachable Debian archive"
    fi
    mv "$rootfs.partial" "$rootfs"
    touch "$stamp"
}

in_root() {
    # Run a command in the root, with /proc, /dev, a fresh /tmp and the checkout at /src; the
    # network settings and CA certificates come from the host (pip behind a proxy needs them).
    cp /etc/resolv.conf "$rootfs/etc/resolv.conf"
    ln -sfn ../proc/self/mounts "$rootfs/etc/mtab"  # Blender lists the mounted file systems
    local ca=/etc/ssl/certs/ca-certificates.crt
    local env=(HOME=/root PATH=/usr/local/bin:/usr/bin:/bin LANG=C.UTF-8 VOODOO_IN_NEXT_ROOT=1)
    if [ -f "$ca" ]; then
        cp "$ca" "$rootfs/etc/ssl/certs/host-ca-certificates.crt"
        env+=(PIP_CERT=/etc/ssl/certs/host-ca-certificates.crt)
        env+=(SSL_CERT_FILE=/etc/ssl/certs/host-ca-certificates.crt)
    fi
    local name
    for name in PIP_INDEX_URL PIP_EXTRA_INDEX_URL PIP_TRUSTED_HOST PIP_DEFAULT_TIMEOUT \
        http_proxy https_proxy no_proxy HTTP_PROXY HTTPS_PROXY NO_PROXY \
        VOODOO_FUZZ_SECONDS VOODOO_FUZZ_SEED; do
        [ -n "${!name:-}" ] && env+=("$name=${!name}")
    done
    mkdir -p "$rootfs/src"
    unshare --mount --propagation private -- /bin/bash -euc '
        root=$1 src=$2
        shift 2
        mount -t proc proc "$root/proc"
        mount --rbind /dev "$root/dev"
        mount -t tmpfs tmpfs "$root/tmp"
        mount --bind "$src" "$root/src"
        exec chroot "$root" /usr/bin/env -i "$@"
    ' in_root "$rootfs" "$checkout" "${env[@]}" "$@"
}

make_venv() {
    local stamp sum
    sum=$(cat "$checkout"/requirements{,-test,-next}.txt | cksum | cut -d' ' -f1)
    stamp=$rootfs$venv/.installed-$sum
    [ -e "$stamp" ] && return 0
    echo "Installing bpy $version with the add-on's and the tests' requirements in the root" >&2
    rm -rf "$rootfs$venv"
    in_root /bin/sh -ec "python3 -m venv $venv
        $venv/bin/python -m pip install -q --upgrade pip
        cd /src && $venv/bin/python -m pip install -q bpy==$version -r requirements-next.txt" \
        || fail "could not install bpy $version in the root (see pip's message above)"
    touch "$stamp"
}

make_root
make_venv
if [ "${1:-}" = --python ]; then
    shift
    run=("$venv/bin/python")
else
    run=("$venv/bin/python" -m pytest -p no:cacheprovider)
fi
echo "Blender $version (CPython 3.13, in $rootfs, checkout at /src): ${run[*]} $*" >&2
in_root /bin/sh -c 'cd /src && exec "$@"' run "${run[@]}" "$@"
