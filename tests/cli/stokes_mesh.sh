#!/usr/bin/env bash
# stokes_mesh.sh NOETHER SOURCE_DIR: `noether shape stokes FILE.obj --density D --units U` (no
# scene) gives the coefficients the scene of that body gives, bit for bit (KW4 Alpha's mesh at
# 1970 kg/m^3, examples/kw4-alpha-orbiter.yaml; GM differs only by the scene's G of 6.674e-11),
# and its mass is the density times the mesh's volume; without --density or --units it is refused.
set -u
noether=$1; src=$2
fail() { echo "stokes_mesh: FAIL: $*"; exit 1; }
mesh="$src/examples/shapes/a66391_1999kw4_primary.obj"
alone=$("$noether" shape stokes "$mesh" --density 1970 --units km --degree 6) || fail "mesh alone: $alone"
scene=$("$noether" shape stokes "$src/examples/kw4-alpha-orbiter.yaml" --body alpha --degree 6) || fail "scene: $scene"
[ "$(grep -v '^#' <<<"$alone")" = "$(grep -v '^#' <<<"$scene")" ] || fail "coefficients differ"
[ "$(grep -c -v '^#' <<<"$alone")" -eq 28 ] || fail "not 28 coefficients to degree 6"
grep -q "body 'a66391_1999kw4_primary' of .*a66391_1999kw4_primary.obj" <<<"$alone" || fail "$alone"
grep -q "mass 2354756811505.875," <<<"$alone" || fail "the mass is not the scene's: $alone"
# The file's own axes (--frame mesh): the same mass, other C22/S22 (the axes are not principal).
framed=$("$noether" shape stokes "$mesh" --density 1970 --units km --degree 2 --frame mesh) || fail "$framed"
[ "$(grep -v '^#' <<<"$framed")" != "$(grep -v '^#' <<<"$alone" | head -6)" ] || fail "--frame mesh changed nothing"
# -o with a name that is not .gfc writes a table (it was refused: "--format must be … not ''").
work=$(mktemp -d) && trap 'rm -rf "$work"' EXIT
"$noether" shape stokes "$mesh" --density 1970 --units km --degree 4 -o "$work/alpha.txt" > /dev/null || fail "-o .txt"
[ "$(grep -c -v '^#' "$work/alpha.txt")" -eq 15 ] || fail "-o alpha.txt is not the 15 rows of degree 4"
out=$("$noether" shape stokes "$mesh" --units km 2>&1); rc=$?
[ "$rc" -eq 2 ] && grep -q "a mesh alone needs --density (kg/m^3" <<<"$out" || fail "no --density: exit $rc: $out"
out=$("$noether" shape stokes "$mesh" --density 1970 2>&1); rc=$?
[ "$rc" -eq 2 ] && grep -q "give --units m or --units km" <<<"$out" || fail "no --units: exit $rc: $out"
out=$("$noether" shape stokes "$src/examples/kw4-alpha-orbiter.yaml" --body alpha --density 1970 2>&1); rc=$?
[ "$rc" -eq 2 ] && grep -q "go with a mesh file" <<<"$out" || fail "--density with a scene: exit $rc: $out"
echo "stokes_mesh: a mesh alone gives the scene's coefficients bit for bit; missing --density/--units refused"
