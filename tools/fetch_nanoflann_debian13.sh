#!/usr/bin/env bash
# Fetches Debian 13 (trixie)'s libnanoflann-dev from the Debian mirror and unpacks it under DIR:
# never installed, the system's nanoflann is untouched. Prints the nanoflann CMake package
# folder (for -Dnanoflann_DIR); progress and errors go to stderr.
# Used by tools/test.sh's nanoflann-next stage (ppcr against a newer nanoflann than Debian 12's).
#   tools/fetch_nanoflann_debian13.sh DIR
#
# The package is pinned: version and SHA-256 below are those trixie's Packages index
# (dists/trixie/main/binary-all/Packages.xz) listed on 2026-11-25, and the download must match
# the SHA-256. That index could not be authenticated when the pin was taken: the mirror served a
# correctly signed InRelease whose SHA-256 for Packages.xz did not match the Packages.xz it served
# (another snapshot), so the pin rests on that one fetch; re-check it against a consistent mirror
# (InRelease via gpgv and the Debian archive keyring, then the index) when updating it. A pool
# file does not change; when trixie moves on and this one leaves the pool, the download fails:
# update the pin then.
set -euo pipefail
dir=${1:?usage: tools/fetch_nanoflann_debian13.sh DIR}
mirror=${PPCR_DEBIAN_MIRROR:-https://deb.debian.org/debian}
version=1.7.1+ds-1
sha256=5a21155e30047aba62adbb4fb5f27156d28ad5bc26bb9e7d97db770735363dfc
url="$mirror/pool/main/n/nanoflann/libnanoflann-dev_${version}_all.deb"
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)

fail() {
  echo "fetch_nanoflann_debian13: $*" >&2
  exit 1
}

curl -fsSL -m 300 -o "$dir/libnanoflann-dev.deb" "$url" || fail "cannot download $url"
echo "$sha256  $dir/libnanoflann-dev.deb" | sha256sum -c --quiet - >&2 ||
  fail "$url does not match the pinned SHA-256 $sha256"
echo "fetch_nanoflann_debian13: libnanoflann-dev $version, SHA-256 checked" >&2
rm -rf "$dir/root"
dpkg-deb -x "$dir/libnanoflann-dev.deb" "$dir/root"
config_file=$(find "$dir/root" -name nanoflannConfig.cmake | head -n 1)
[[ -n $config_file ]] || fail "no nanoflannConfig.cmake in $url"
dirname "$config_file"
