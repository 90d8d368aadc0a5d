#!/bin/sh
# The geoscni program: help and version exit 0, usage errors exit 2, every
# subcommand has --help.
set -u
geoscni=$1
failures=0
expect_status() {
    expected=$1
    shift
    "$@" >/tmp/geoscni-cli-out.$$ 2>&1
    status=$?
    if [ "$status" -ne "$expected" ]; then
        echo "FAIL: '$*' exited $status, expected $expected"
        cat /tmp/geoscni-cli-out.$$
        failures=$((failures + 1))
    fi
}
expect_output() {
    if ! grep -q -- "$1" /tmp/geoscni-cli-out.$$; then
        echo "FAIL: output lacks '$1'"
        cat /tmp/geoscni-cli-out.$$
        failures=$((failures + 1))
    fi
}
expect_status 0 "$geoscni" --help
expect_output "commands:"
expect_status 0 "$geoscni" --version
for library in gmsh CGAL HDF5 VTK; do expect_output "$library"; done
for command in pre solve post run check; do
    expect_status 0 "$geoscni" $command --help
    expect_output "usage: geoscni $command"
done
expect_status 2 "$geoscni"
expect_status 2 "$geoscni" frobnicate
expect_output "unknown command 'frobnicate'"
expect_status 2 "$geoscni" pre
expect_output "pre needs a file"
expect_status 2 "$geoscni" pre valid.yaml --bogus
expect_output "unknown option '--bogus'"
expect_status 2 "$geoscni" solve valid.yaml minimal.yaml
expect_status 0 "$geoscni" check valid.yaml minimal.yaml
expect_output "bulk_modulus: 27400000"
expect_status 2 "$geoscni" check no_such_case.yaml
expect_output "cannot open the case file"
rm -f /tmp/geoscni-cli-out.$$
echo "$failures failures"
[ "$failures" -eq 0 ]
