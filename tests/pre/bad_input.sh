#!/bin/sh
# geoscni pre on bad input (issue 3, point 6): a message and exit status 2
# for each case, and no model.h5 (whole or partial) left in the output folder.
# Each run has 60 s: pre must refuse, never wait.
# Usage: bad_input.sh GEOSCNI_BINARY   (run from tests/pre)
set -u
geoscni=$1
work=$(mktemp -d /tmp/geoscni_pre_bad.XXXXXX)
trap 'rm -rf "$work"' EXIT
failures=0

# expect NAME EXPECTED_TEXT geoscni-arguments...
expect() {
    name=$1 text=$2
    shift 2
    timeout 60 "$geoscni" "$@" >"$work/out" 2>"$work/err"
    status=$?
    if [ "$status" -ne 2 ]; then
        echo "FAIL $name: exit status $status, expected 2"
        cat "$work/err"
        failures=$((failures + 1))
    elif ! grep -q "$text" "$work/err"; then
        echo "FAIL $name: the message does not say '$text':"
        cat "$work/err"
        failures=$((failures + 1))
    else
        echo "ok   $name: $(head -n 1 "$work/err")"
    fi
    if find "$work" -name 'model.h5*' | grep -q .; then
        echo "FAIL $name: a model.h5 was left behind"
        failures=$((failures + 1))
    fi
}

expect no_volume "has no volume" \
    pre cases/no_volume.yaml -o "$work/out_no_volume"
expect unmeshable "the surfaces do not close a volume" \
    pre cases/unmeshable.yaml -o "$work/out_unmeshable"
expect missing_surface "boundary 'footing' names no physical surface" \
    pre cases/missing_surface.yaml -o "$work/out_missing_surface"
expect too_many "more than 5000000" \
    pre cases/too_many.yaml -o "$work/out_too_many"
# gmsh asks "Do you really want to continue?" on stdin before meshing a
# geometry whose point sizes are tiny against it: with stdin a pipe held open
# and never written, pre must still refuse at once
mkfifo "$work/stdin"
exec 3<>"$work/stdin"
expect too_many_stdin_open "more than 5000000" \
    pre cases/too_many.yaml -o "$work/out_too_many_stdin" <"$work/stdin"
exec 3>&-
expect symmetry_slanted \
    "symmetry_slanted.yaml:8: 'boundary.face.symmetry': surface 'face' is not one plane normal to x, y or z" \
    pre cases/symmetry_slanted.yaml -o "$work/out_symmetry_slanted"
expect refine_missing_surface \
    "refine_missing_surface.yaml:7: 'particles.refine\[0\].surface' is 'footing', which is not a physical surface" \
    pre cases/refine_missing_surface.yaml -o "$work/out_refine_missing_surface"
touch "$work/a_file"
expect unwritable_outdir "cannot create the output folder" \
    pre ../../geometries/box.yaml -o "$work/a_file/out"

# negative control: the same binary succeeds on good input
if "$geoscni" pre -q ../../geometries/box.yaml -o "$work/out_good" &&
    [ -f "$work/out_good/model.h5" ] && [ ! -e "$work/out_good/model.h5.part" ]; then
    echo "ok   good input: model.h5 written"
else
    echo "FAIL good input"
    failures=$((failures + 1))
fi
rm -rf "$work/out_good"
if find "$work" -name 'model.h5*' | grep -q .; then
    echo "FAIL: a model.h5 was left behind by a failed run"
    failures=$((failures + 1))
fi
echo "bad_input: $failures failed"
[ "$failures" -eq 0 ]
