#!/bin/sh
# Installs what is missing, builds geoscni, and runs the default case (the
# coarse Slope I) into out/slope_I_coarse. Usage: sh scripts/run-demo.sh
set -eu
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)

sh scripts/setup-debian.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$jobs"
./build/bin/geoscni run geometries/slope_I_coarse.yaml -o out/slope_I_coarse
echo "open out/slope_I_coarse/slope_I_coarse.pvd in ParaView"
