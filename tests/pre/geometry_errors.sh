#!/bin/sh
# Geometry mistakes (issue 21, points 1, 3, 6, 7): check, pre and run each
# exit with status 2 and a message that names the .geo and says what to
# change, in seconds, never SIGABRT, never exit 0 with nothing, never a
# model.h5. The cases are in cases/geometry/ (the issue's reproducers and
# variants of them); every case of geometries/ passes check (no false alarm).
# Usage: geometry_errors.sh GEOSCNI_BINARY   (run from tests/pre)
set -u
geoscni=$1
cases=cases/geometry
work=$(mktemp -d /tmp/geoscni_geometry.XXXXXX)
trap 'rm -rf "$work"' EXIT
failures=0

fail() {
    echo "FAIL $*"
    failures=$((failures + 1))
}

# expect NAME SECONDS TEXT geoscni-arguments...: exit status 2 within
# SECONDS, TEXT (fixed string) in the first line of the error, no model.h5
expect() {
    name=$1 seconds=$2 text=$3
    shift 3
    start=$(date +%s)
    timeout 120 "$geoscni" "$@" >"$work/out" 2>"$work/err"
    status=$?
    took=$(($(date +%s) - start))
    if [ "$status" -ne 2 ]; then
        fail "$name: exit status $status, expected 2"
        cat "$work/err"
    elif ! head -n 1 "$work/err" | grep -qF -- "$text"; then
        fail "$name: the message does not say '$text':"
        cat "$work/err"
    elif [ "$took" -gt "$seconds" ]; then
        fail "$name: took $took s, more than $seconds"
    else
        echo "ok   $name ($took s): $(head -n 1 "$work/err")"
    fi
    if find "$work" -name 'model.h5*' | grep -q .; then
        fail "$name: a model.h5 was left behind"
        find "$work" -name 'model.h5*' -exec rm -f {} +
    fi
}

# expect_all NAME TEXT: the same through check, pre and run
expect_all() {
    expect "$1 (check)" 30 "$2" check "$cases/$1.yaml"
    expect "$1 (pre)" 30 "$2" pre "$cases/$1.yaml" -o "$work/out_$1"
    expect "$1 (run)" 30 "$2" run "$cases/$1.yaml" -o "$work/out_$1"
}

geo=$(cd "$cases" && pwd -P)

# point 1: gmsh failures become exit 2 with gmsh's message and the .geo
expect_all zero_length_edge \
    "$geo/zero_length_edge.geo: curve 6 has zero length: it joins points 6 and 7, which are both at (8, 0, 6); use one point there"
expect_all coincident_points \
    "$geo/coincident_points.geo: points 5 and 9 are both at (0, 0, 1); use one point there"
expect_all site_y_shifted \
    "$geo/site_y_shifted.geo: the geometry lies 4.48e+06 m from the origin"
# an abort in gmsh's mesher that no check before meshing foresees: the
# child process that meshes dies, and its parent says why
expect_all bowtie \
    "$geo/bowtie.geo: gmsh failed while meshing it coarsely to estimate the particle count: Unable to recover the edge"

# point 3: a .geo that stops gmsh's parser
expect_all exit_end \
    "$geo/exit_end.geo:47: 'Exit;' ends gmsh, and the program with it, while it reads the geometry; delete it"
expect_all exit_included \
    "$geo/exit_included.geo: gmsh ended the program while reading it (does the geometry, or a file it includes, end with 'Exit;'?)"
expect_all abort_start \
    "$geo/abort_start.geo:2: gmsh stops reading the geometry at 'Abort;', before it defines a volume"
# a batch: the bad case is named, nothing runs, exit 2 (not 0)
expect "exit_end in a batch (run)" 30 "$geo/exit_end.geo:47: 'Exit;' ends gmsh" \
    run ../../geometries/box.yaml "$cases/exit_end.yaml" -o "$work/batch"

# point 7: what to change
expect_all site_utm \
    "translate the geometry near the origin, e.g. subtract (512345, 4467890, 229) from its coordinates"
expect_all open_loop \
    "$geo/open_loop.geo: the surfaces do not close a volume: volume 1 is bounded by surfaces that leave a gap"
expect_all touching \
    "$geo/touching.geo: volumes 1 and 2 touch without sharing a face"
expect_all touching_occ \
    "$geo/touching_occ.geo: volumes 1 and 2 touch without sharing a face (surfaces 6 and 11 lie on each other"
expect_all spacing_too_large \
    "spacing_too_large.yaml:3: 'particles.spacing' (1.5 m) is larger than the body of"

# point 6: the particle limit before any meshing at the refine spacings
# (refine_guard grew to 9.3 GB in 10 minutes)
for guard in refine_guard refine_box_guard refine_thin_guard; do
    expect "$guard (pre)" 15 "more than 5000000" \
        pre "$cases/$guard.yaml" -o "$work/out_$guard"
    expect "$guard (run)" 15 "more than 5000000" \
        run "$cases/$guard.yaml" -o "$work/out_$guard"
done

# negative controls: faces shared by fragmented volumes, and every case of
# geometries/, pass check
for case in "$cases/fragments.yaml" ../../geometries/*.yaml; do
    if timeout 120 "$geoscni" check -q "$case" 2>"$work/err"; then
        echo "ok   $case passes check"
    else
        fail "$case: check failed:"
        cat "$work/err"
    fi
done
echo "geometry_errors: $failures failed"
[ "$failures" -eq 0 ]
