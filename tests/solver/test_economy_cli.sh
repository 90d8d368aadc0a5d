#!/bin/sh
# Economy through the CLI (issue 8; docs/economy.md): the half box
# (cases/half_box.yaml: a symmetry plane at x = 1, frames with displacement
# and stress only, mirrored by post) against the whole box
# (cases/economy_box.yaml). check_economy.py reads the files back; the
# whole box's top force must be twice the half's; post notes the pictures
# it cannot draw without damage and equivalent stress.
# usage: test_economy_cli.sh GEOSCNI   (run from tests/solver)
. ./cli_testing.sh

"$geoscni" run cases/half_box.yaml -o "$out/half" >"$out/half.log" 2>&1 ||
    fail "run half_box: $(cat "$out/half.log")"
grep -q "post: mirrored across 'symmetry' (x = 1 m)" "$out/half.log" ||
    fail "post did not mirror: $(cat "$out/half.log")"
if grep -q "skipped the pictures" "$out/half.log"; then
    echo "no display: the notes on absent fields are not checked"
else
    grep -q "no damage pictures: the results hold no 'damage'" "$out/half.log" ||
        fail "no note on the damage pictures: $(cat "$out/half.log")"
    grep -q "no clip pictures: the results hold no 'equivalent_stress'" "$out/half.log" ||
        fail "no note on the stress picture: $(cat "$out/half.log")"
    [ -s "$(ls "$out"/half/pictures/clip_uz_frame_*.png 2>/dev/null | tail -1)" ] ||
        fail "the u_z picture of the displacement that was written is missing"
    [ -e "$out/half/pictures/damage_frame_0000.png" ] &&
        fail "a damage picture without damage"
fi
/usr/bin/python3 check_economy.py "$out/half" 1.0 displacement stress ||
    fail "check_economy.py"

"$geoscni" run cases/economy_box.yaml -o "$out/whole" --no-pictures -q ||
    fail "run economy_box"
# top_fz of the last row: the whole box's against twice the half's, loaded
# quasi-statically (ramp and damping; a sudden load left a wave whose phase
# at the last row differed by mesh, 2 % to 5 % on gmsh's non-reproducible
# meshes). The two meshes differ: they agree to about 1 %. 5 % catches a wrong factor; the plane itself
# is checked by check_economy.py (u_x on it), because in this load case the
# force without the plane is only 1 % lower.
force() {
    awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "top_fz_N") c = i }
             END { print $c }' "$1"
}
whole=$(force "$out/whole/history.csv")
half=$(force "$out/half/history.csv")
echo "top force: whole $whole N, half $half N (doubled $(echo "$half" | awk '{print 2 * $1}') N)"
echo "$whole $half" | awk '{ d = (2 * $2 - $1) / $1; exit !(d < 0.05 && d > -0.05) }' ||
    fail "twice the half's force is not the whole's within 5 %"
finish
