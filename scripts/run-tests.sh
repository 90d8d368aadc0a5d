#!/bin/sh
# Installs what is missing, builds geoscni (Release and ASan+UBSan), and runs
# the whole test suite with ctest: every test in the Release build but the
# long ones (label slow), the unit tests again under the sanitizers.
# Usage: sh scripts/run-tests.sh
set -eu
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)

sh scripts/build.sh build
ctest --test-dir build --output-on-failure -LE slow -j"$jobs" --timeout 900

sh scripts/build.sh build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEOSCNI_SANITIZE=ON
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
export LSAN_OPTIONS="suppressions=$(pwd)/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build-asan --output-on-failure -L unit -j"$jobs" --timeout 900
