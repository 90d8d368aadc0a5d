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
# stop_at_rows PID FILE N: once FILE has N lines (or after 60 s), SIGTERM
# to PID and wait for it; its exit status in stopped_status.
stop_at_rows() {
    i=0
    while [ "$(if [ -f "$2" ]; then wc -l <"$2"; else echo 0; fi)" -lt "$3" ] &&
        [ $i -lt 1200 ]; do
        sleep 0.05
        i=$((i + 1))
    done
    kill -TERM "$1"
    wait "$1"
    stopped_status=$?
}
finish() {
    echo "$failures failures"
    [ "$failures" -eq 0 ]
}
