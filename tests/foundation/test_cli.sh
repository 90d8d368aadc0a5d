#!/bin/sh
# The geoscni program: help and version exit 0, usage errors exit 2 and say
# what is allowed, every subcommand has --help, option values also after '='
# or the letter, options a command does not use are refused; check shows
# numbers in their shortest exact form and checks every file it is given.
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
expect_output "solve takes one file"
expect_output "(see geoscni solve --help)"
expect_status 2 "$geoscni" frobnicate
expect_output "(see geoscni --help)"
expect_status 2 "$geoscni" post
expect_output "post needs a folder"
expect_status 2 "$geoscni" post a b
expect_output "post takes one folder"
expect_status 0 "$geoscni" run --help
expect_output "--restart"
expect_output "interrupted solve"
# the value of -j and -o: a separate word, after '=', or after the letter;
# a bad count is refused before the case file is read
for threads in "-j 0" "-j0" "--threads 0" "--threads=0"; do
    expect_status 2 "$geoscni" pre no_such_case.yaml $threads
    expect_output "bad thread count '0': give a whole number of at least 1"
done
expect_status 2 "$geoscni" pre no_such_case.yaml --threads=x2
expect_output "bad thread count 'x2'"
for output in "-o" "--output"; do
    expect_status 2 "$geoscni" pre no_such_case.yaml $output
    expect_output "$output needs a folder"
done
expect_status 2 "$geoscni" pre no_such_case.yaml --force=yes
expect_output "--force takes no value"
# accepted: the run goes on to read the case, which is missing
for options in "-j2" "--threads=2" "-j 2" "--output=/tmp/x" "-o/tmp/x"; do
    expect_status 2 "$geoscni" pre no_such_case.yaml $options
    expect_output "cannot open the case file"
done
# an option the command does not use, named with the command
expect_status 2 "$geoscni" check -o foo valid.yaml
expect_output "check does not take -o (--output)"
expect_status 2 "$geoscni" post --force folder
expect_output "post does not take --force"
expect_status 2 "$geoscni" check valid.yaml -j2
expect_output "check does not take -j (--threads)"
expect_status 2 "$geoscni" pre no_such_case.yaml --restart
expect_output "pre does not take --restart"
expect_status 0 "$geoscni" check valid.yaml minimal.yaml
expect_output "bulk_modulus: 27400000"
# numbers shown in their shortest exact form (0.07, not 0.070000000000000007)
expect_output "alpha: 0.07, R: 190000"
# every file is checked: the bad one named, the good ones printed, exit 2
expect_status 2 "$geoscni" check valid.yaml bad/geometry_folder.yaml minimal.yaml
expect_output "geometry_folder.yaml:3: geometry '..' is a folder"
expect_output "resolved parameters of minimal.yaml"
expect_status 2 "$geoscni" check no_such_case.yaml
expect_output "cannot open the case file"
rm -f /tmp/geoscni-cli-out.$$
echo "$failures failures"
[ "$failures" -eq 0 ]
