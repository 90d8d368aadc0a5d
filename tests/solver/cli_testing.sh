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
# wait_for_file FILE SECONDS: until FILE is not empty, at most SECONDS.
wait_for_file() {
    i=0
    while [ ! -s "$1" ] && [ $i -lt $(($2 * 10)) ]; do
        sleep 0.1
        i=$((i + 1))
    done
}
# PID runs with libgomp's short spin (app/geoscni.c, exec_with_short_spin)
# unless the wait policy was given; WHAT names it in the message
check_short_spin() {
    if [ -z "${OMP_WAIT_POLICY:-}${GOMP_SPINCOUNT:-}" ] && [ -r /proc/$1/environ ]; then
        tr '\0' '\n' </proc/$1/environ | grep -qx 'GOMP_SPINCOUNT=3000' ||
            fail "$2 does not run with GOMP_SPINCOUNT=3000"
    fi
}
finish() {
    echo "$failures failures"
    [ "$failures" -eq 0 ]
}
