# Shared by the CLI tests of this folder (sourced as `. ./cli_testing.sh`
# with the test's arguments): geoscni is the first argument, out a scratch
# folder removed on exit, fail MESSAGE counts a failure, and finish prints
# the count and ends with status 0 only if there was none.
set -u
geoscni=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
finish() {
    echo "$failures failures"
    [ "$failures" -eq 0 ]
}
