#!/bin/sh
# check.sh LAYERFIT: `layerfit check`.  Each bad input must give exit status
# 2, exactly one message on stderr and nothing on stdout; good inputs give
# the report and their warnings.  Last line: "N passed, N failed".
lf=$1
cd "$(dirname "$0")/../.." || exit 1
pass=0; fail=0
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# expect CODE STDERR ARGS...: exit status and whole stderr; stdout must be
# empty unless CODE is 0.
expect() {
    code=$1; want=$2; shift 2
    "$lf" "$@" >"$tmp/out" 2>"$tmp/err"; rc=$?
    got=$(cat "$tmp/err")
    if [ "$rc" -eq "$code" ] && [ "$got" = "$want" ] \
       && { [ "$code" -eq 0 ] || [ ! -s "$tmp/out" ]; }; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        echo "FAIL: layerfit $*"
        echo "  exit $rc, want $code"
        echo "  stderr: $got"
        echo "  want:   $want"
        [ "$code" -ne 0 ] && [ -s "$tmp/out" ] && echo "  stdout should be empty"
    fi
}
# stdout_is TEXT: the stdout of the last expect, exactly
stdout_is() {
    if [ "$(cat "$tmp/out")" = "$1" ]; then pass=$((pass + 1)); else
        fail=$((fail + 1)); echo "FAIL: stdout"; cat "$tmp/out"; echo "  want:"; echo "$1"; fi
}

b=tests/data/bad
# files that cannot be read
expect 2 "layerfit: $b/none.csv: cannot open: No such file or directory" check $b/none.csv
expect 2 "layerfit: $b: is a directory (expected a CSV file)" check $b
expect 2 "layerfit: $b/curve_empty.csv: empty file (expected a header such as depth_nm,force_uN and one row per point)" check $b/curve_empty.csv
expect 2 "layerfit: $b/curve_header_only.csv:1: header but no data rows (expected one row of depth_nm and force_uN per point below it)" check $b/curve_header_only.csv
expect 2 "layerfit: $b/curve_binary.csv: a PNG image, not a curve file" check $b/curve_binary.csv
expect 2 "layerfit: $b/curve_utf16.csv:1:1: UTF-16 text (save the file as UTF-8 CSV)" check $b/curve_utf16.csv
# headers
expect 2 "layerfit: $b/curve_no_depth.csv:1:1: no depth column in the header (name one depth, indentation, displacement or delta, with its unit, e.g. depth_nm)" check $b/curve_no_depth.csv
expect 2 "layerfit: $b/curve_no_force.csv:1:1: no force column in the header (name one force, load or P, with its unit, e.g. force_uN)" check $b/curve_no_force.csv
expect 2 "layerfit: $b/curve_two_depth.csv:1:19: second depth column 'Indentation [um]' (column 'depth_nm' is the depth already; keep one, or rename the other)" check $b/curve_two_depth.csv
expect 2 "layerfit: $b/curve_unknown_unit.csv:1:1: depth column 'depth_bogus': unknown unit 'bogus' (expected a length such as 1um)" check $b/curve_unknown_unit.csv
expect 2 "layerfit: $b/curve_wrong_unit.csv:1:12: force column 'Load (s)': unit 's' is a time, not a force (e.g. 10uN)" check $b/curve_wrong_unit.csv
expect 2 "layerfit: $b/curve_no_unit.csv:1:1: depth column 'depth' has no unit (name it in the header, e.g. depth_nm or depth (nm), or give --depth-unit)" check $b/curve_no_unit.csv
expect 2 "layerfit: $b/curve_data_first.csv:1:1: the first row is data, not a header (start with a header naming the columns, e.g. depth_nm,force_uN)" check $b/curve_data_first.csv
# cells and rows
expect 2 "layerfit: $b/curve_not_number.csv:3:3: force_uN 'abc' is not a number (expected a decimal number such as 12.5)" check $b/curve_not_number.csv
expect 2 "layerfit: $b/curve_nan.csv:3:1: depth_nm 'NaN' is not a finite number (give a measured value, or delete the row)" check $b/curve_nan.csv
expect 2 "layerfit: $b/curve_inf.csv:3:3: force_uN '-Inf' is not a finite number (give a measured value, or delete the row)" check $b/curve_inf.csv
expect 2 "layerfit: $b/curve_ragged.csv:3:4: row has 2 cells, the header 3 (every row needs a cell in each column; --skip-bad-rows skips such rows)" check $b/curve_ragged.csv
expect 2 "layerfit: $b/curve_ragged_long.csv:3:5: row has 3 cells, the header 2 (is the delimiter ',' used inside a number? quote such cells)" check $b/curve_ragged_long.csv
expect 2 "layerfit: $b/curve_quote.csv:3:3: quote opened here is never closed (end the field with \")" check $b/curve_quote.csv
expect 2 "layerfit: $b/curve_bad_quote.csv:3:4: malformed quotes (quote a whole field, and double the quotes inside it: \"a \"\"b\"\"\")" check $b/curve_bad_quote.csv
expect 2 "layerfit: $b/curve_segment_word.csv:3:5: unknown segment 'creep' (expected load, approach, extend, hold, pause, dwell, unload, retract or withdraw)" check $b/curve_segment_word.csv
{ echo depth_nm,force_uN; echo 1,2; head -c 1048577 /dev/zero | tr '\0' 7; echo; } >"$tmp/long.csv"
expect 2 "layerfit: $tmp/long.csv:3: line longer than 1 MiB (lines must end within 1048576 bytes; is this a CSV file?)" check "$tmp/long.csv"
# data a fit cannot use
expect 2 "layerfit: $b/curve_few_points.csv:4: the unloading segment has 3 points (a fit needs at least 6)" check $b/curve_few_points.csv
expect 2 "layerfit: $b/curve_zero_force.csv:4: force is 0 at every point of the unloading segment (is the force column the right one?)" check $b/curve_zero_force.csv
expect 2 "layerfit: $b/curve_flat_depth.csv:2: depth is 1e-08 m at every point of the unloading segment (is the depth column the right one?)" check $b/curve_flat_depth.csv
# plans
expect 2 "layerfit: $b/plan_missing_curve.csv:3: curve file $b/no_such_curve.csv: cannot open: No such file or directory (paths are relative to the plan's folder)" check $b/plan_missing_curve.csv
expect 2 "layerfit: $b/plan_k_zero.csv:2:20: k must be a finite number > 0 (got 0)" check $b/plan_k_zero.csv
expect 2 "layerfit: $b/plan_negative_R.csv:2:22: R must be a finite length > 0 (got -0.001 m)" check $b/plan_negative_R.csv
expect 2 "layerfit: $b/plan_negative_b.csv:2:24: b must be a finite length > 0 (got -1e-06 m)" check $b/plan_negative_b.csv
expect 2 "layerfit: $b/plan_nu_bonded.csv:3:37: nu must lie in [0, 0.5) for a bonded layer (got 0.5) (leave nu empty to fit it)" check $b/plan_nu_bonded.csv
expect 2 "layerfit: $b/plan_interface.csv:2:26: unknown interface 'glued' (expected frictionless or bonded)" check $b/plan_interface.csv
expect 2 "layerfit: $b/plan_duplicate.csv:4:1: duplicate row: curve './../curve_comma.csv' and segment unload are listed at line 2 already (list each once)" check $b/plan_duplicate.csv
expect 2 "layerfit: $b/plan_unknown_column.csv:1:28: unknown column 'colour' (a plan has the columns file,k,R,b,interface and may add nu,segment,sample,z0,F0,format,index,tip,half_angle,prefactor,depth_range,force_range)" check $b/plan_unknown_column.csv
expect 2 "layerfit: $b/plan_no_b.csv:1:1: no b column in the header (a plan has the columns file,k,R,b,interface and may add nu,segment,sample,z0,F0,format,index,tip,half_angle,prefactor,depth_range,force_range)" check $b/plan_no_b.csv
expect 2 "layerfit: $b/plan_cell_unit.csv:2:22: R '1mm' is not a number (the header gives the unit, so a bare number such as 1.5)" check $b/plan_cell_unit.csv
expect 2 "layerfit: $b/curve_nan.csv:3:1: depth_nm 'NaN' is not a finite number (give a measured value, or delete the row)" check $b/plan_bad_curve.csv
# the command line
expect 2 "layerfit: check: expected one file, a plan or a curve (e.g. layerfit check plan.csv)" check
expect 2 "layerfit: check: expected one file, a plan or a curve (e.g. layerfit check plan.csv)" check a.csv b.csv
expect 2 "layerfit: check: unknown option '--depth' (see 'layerfit check --help')" check --depth nm a.csv
expect 2 "layerfit: tests/data/curve_nounit.csv: --depth-unit: unit 'N' is a force, not a length (e.g. 1um)" check --depth-unit N --force-unit uN tests/data/curve_nounit.csv

# good input
d=tests/data
expect 0 "" check $d/curve_comma.csv
stdout_is "curve $d/curve_comma.csv
  format    csv
  found     header: line 3, delimiter ','
  found     depth: column 1 'depth_nm' in nm (from the header), x 1e-09 to m
  found     force: column 2 'force_uN' in uN (from the header), x 1e-06 to N
  found     segments from the depth profile: split at its extreme (line 8), no hold
  points    10 (load 4, unload 6)
  depth     -6 nm .. 30 nm
  force     -3.5 µN .. 85.25 µN
  fit       unload segment, 6 points
  metadata  instrument: Synthetic Indenter 3000
  metadata  tip: sphere, R = 1 mm"
expect 0 "" check --depth-unit=nm --force-unit uN $d/curve_nounit.csv
stdout_is "curve $d/curve_nounit.csv
  format    csv
  found     header: line 1, delimiter ','
  found     depth: column 1 'Depth' in nm (from --depth-unit), x 1e-09 to m
  found     force: column 2 'Force' in uN (from --force-unit), x 1e-06 to N
  found     segments from the depth profile: split at its extreme (line 5), no hold
  points    9 (load 3, unload 6)
  depth     -2 nm .. 3 nm
  force     -1 µN .. 9 µN
  fit       unload segment, 6 points"
# hold words in a segment column: a hold, counted, never fitted
expect 0 "" check $d/curve_hold_column.csv
stdout_is "curve $d/curve_hold_column.csv
  format    csv
  found     header: line 2, delimiter ','
  found     depth: column 2 'Depth (nm)' in nm (from the header), x 1e-09 to m
  found     force: column 3 'Load (µN)' in uN (from the header), x 1e-06 to N
  found     time: column 1 'Time (s)' in s (from the header), x 1 to s
  found     segments: from column 4 'Segment' (load 5, hold 4, unload 6 points)
  points    15 (load 5, hold 4 (not fitted), unload 6)
  depth     -2 nm .. 20 nm
  force     -900 nN .. 12 µN
  time      0 s .. 14 s
  fit       unload segment, 6 points
  metadata  instrument: synthetic creep test with a marked hold"
expect 2 "layerfit: $d/curve_skip.csv:3:3: empty force cell (every row needs a cell in each column; --skip-bad-rows skips such rows)" check $d/curve_skip.csv
expect 0 "layerfit: warning: $d/curve_skip.csv:3: skipped 2 rows with missing cells (first here)" check --skip-bad-rows $d/curve_skip.csv
expect 0 "layerfit: warning: $d/curve_paren_crlf.csv:5: dropped 1 comment line (first here; only '# key: value' lines above the header are kept, as metadata)
layerfit: warning: $d/curve_bracket.tsv:12: depth increases at 1 point of the unloading segment (first here)" check $d/plan_good.csv
stdout_is "plan $d/plan_good.csv: 4 curves
$d/curve_comma.csv (plan line 3)
  probe     k = 2, R = 1 mm, b = 1 µm, frictionless
  sample    film-A
  nu        not seen (a frictionless curve does not depend on it)
  z0        free
  F0        free
  format    csv
  found     header: line 3, delimiter ','
  found     depth: column 1 'depth_nm' in nm (from the header), x 1e-09 to m
  found     force: column 2 'force_uN' in uN (from the header), x 1e-06 to N
  found     segments from the depth profile: split at its extreme (line 8), no hold
  points    10 (load 4, unload 6)
  depth     -6 nm .. 30 nm
  force     -3.5 µN .. 85.25 µN
  fit       unload segment, 6 points
  metadata  instrument: Synthetic Indenter 3000
  metadata  tip: sphere, R = 1 mm
$d/curve_paren_crlf.csv (plan line 4)
  probe     k = 3, R = 1.5 mm, b = 1 µm, frictionless
  sample    film-A
  nu        not seen (a frictionless curve does not depend on it)
  z0        15 nm (fixed)
  F0        free
  format    csv
  found     header: line 1, delimiter ','
  found     depth: column 1 'Depth (nm)' in nm (from the header), x 1e-09 to m
  found     force: column 2 'Load (µN)' in uN (from the header), x 1e-06 to N
  found     time: column 3 'Time (s)' in s (from the header), x 1 to s
  found     ignored: column 4 'Note'
  found     segments from the depth profile: split at its extreme (line 8), no hold
  points    9 (load 3, unload 6)
  depth     -6 nm .. 30 nm
  force     -500 nN .. 9 µN
  time      0 s .. 8 s
  fit       unload segment, 6 points
$d/curve_bracket.tsv (plan line 5)
  probe     k = 2, R = 1 mm, b = 1 µm, bonded
  sample    film-B
  nu        0.35 (fixed)
  z0        free
  F0        -2 µN (fixed)
  format    csv
  found     header: line 2, delimiter tab
  found     depth: column 1 'Indentation [um]' in um (from the header), x 1e-06 to m
  found     force: column 2 'Force [mN]' in mN (from the header), x 0.001 to N
  found     segments: from column 3 'segment' (load 6, hold 0, unload 7 points)
  points    13 (load 6, unload 7)
  depth     -4 nm .. 20 nm
  force     -10 µN .. 310 µN
  fit       load segment, 6 points
  metadata  sample: PDMS 1 um
$d/curve_semicolon.csv (plan line 6)
  probe     k = 2, R = 1 mm, b = 1 µm, bonded
  sample    film-B
  nu        free
  z0        free
  F0        free
  format    csv
  found     header: line 1, delimiter ';', decimal comma
  found     depth: column 1 'displacement_m' in m (from the header), x 1 to m
  found     force: column 2 'force_N' in N (from the header), x 1 to N
  found     segments from the depth profile: split at its extreme (line 4), no hold
  points    8 (load 2, unload 6)
  depth     -1 nm .. 30 nm
  force     -500 nN .. 10 µN
  fit       unload segment, 6 points"
"$lf" check --help >"$tmp/out" 2>&1 && grep -q -- '--skip-bad-rows' "$tmp/out" \
    && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL: check --help"; }
if [ -d datasets ]; then
    expect 0 "" check datasets/plan.csv
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
