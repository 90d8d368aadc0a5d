#!/bin/sh
# Installs the Debian 12 packages that geoscni needs to build, test and render.
# Idempotent: packages already installed are skipped; needs root (or sudo).
set -eu

packages="build-essential cmake pkg-config clang-format time
libgmsh-dev gmsh libcgal-dev libgmp-dev libmpfr-dev libhdf5-dev hdf5-tools zlib1g-dev
libvtk9-dev python3-vtk9 python3-numpy python3-meshio python3-h5py
libyaml-dev libsuitesparse-dev xvfb xauth libgl1-mesa-dri"

missing=""
for p in $packages; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $p"
    fi
done

if [ -z "$missing" ]; then
    echo "setup: all packages already installed"
    exit 0
fi

sudo_cmd=""
if [ "$(id -u)" -ne 0 ]; then
    sudo_cmd="sudo"
fi
echo "setup: installing$missing"
export DEBIAN_FRONTEND=noninteractive
$sudo_cmd apt-get update -qq
# shellcheck disable=SC2086
$sudo_cmd apt-get install -y -qq --no-install-recommends $missing >/dev/null
echo "setup: done"
