#!/bin/sh
# Installs what is missing, builds geoscni, and runs the default case (the
# coarse Slope I) into out/slope_I_coarse. Usage: sh scripts/run-demo.sh
set -eu
cd "$(dirname "$0")/.."
sh scripts/build.sh
./build/bin/geoscni run geometries/slope_I_coarse.yaml -o out/slope_I_coarse
echo "open out/slope_I_coarse/slope_I_coarse.pvd in ParaView"
