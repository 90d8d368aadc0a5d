#!/bin/sh
# Installs what is missing and builds geoscni into build/ (Release), or into
# FOLDER with the given CMake options. Usage: sh scripts/build.sh [FOLDER [OPTIONS...]]
set -eu
cd "$(dirname "$0")/.."
folder=${1:-build}
[ $# -gt 0 ] && shift
sh scripts/setup-debian.sh
cmake -S . -B "$folder" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$folder" -j"$(nproc 2>/dev/null || echo 2)"
