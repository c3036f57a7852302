#!/bin/sh
# archives.sh: binary exports and force maps on the command line: `check`
# lists a map's curves or shows one (FILE#N), `fit FILE#N` fits one curve,
# `fit --batch MAP --k ...` fits every curve with its position and grid
# place, `layerfit map` draws them, a plan names curves by FILE#N or its
# index column, a joint fit refuses a whole map, and a file no reader takes
# is said for what it is.
. "$(dirname "$0")/common"
v=$top/datasets/vendors
real=$top/../shared/realdata

# check: the listing of a map, one curve of it, a single binary curve
run_ok check "$v/jpk_map.jpk-force-map" && {
    has "check map: format" "$tmp/out" "  format    jpk-force"
    has "check map: count" "$tmp/out" "  curves    6: a fit takes one ($v/jpk_map.jpk-force-map#0 .. #5"
    has "check map: curve 3 back and forth" "$tmp/out" "  3      120 µm      210 µm      2,1        80      40, 0, 40"
}
run_ok check "$v/jpk_map.jpk-force-map#3" && {
    has "check map#3: named" "$tmp/out" "curve $v/jpk_map.jpk-force-map#3"
    has "check map#3: position" "$tmp/out" "position  x 120 µm, y 210 µm (grid column 2, row 1)"
    has "check map#3: constants" "$tmp/out" "found     spring constant 0.032 N/m (file header 'vDeflection force conversion')"
}
run_ok check "$v/nanoscope.spm" && \
    has "check nanoscope: data" "$tmp/out" "data: 1 curve of 64 approach + 64 retract points, 2-byte little-endian integers at byte 8192"
run_ok check "$v/igor.ibw" && \
    has "check igor: segments" "$tmp/out" "segments: from the note's Indexes"
run_ok check "$v/hysitron.hld" && \
    has "check hld: other tables" "$tmp/out" "not used: Sample Approach (4 rows), Drift Measurement (5 rows)"
run_ok check "$v/afmformats.tab" && \
    has "check tab: glued row read" "$tmp/out" "points    80 (load 40, unload 40)"
# a pipe: read once, whole
if cat "$v/jpk_force.jpk-force" | "$LF" check /dev/stdin >"$tmp/out" 2>"$tmp/err"; then
    ok; has "check from a pipe" "$tmp/out" "  format    jpk-force"
else bad "check from a pipe: $(cat "$tmp/err")"; fi
expect_fail 2 "layerfit: $v/jpk_calibration.jpk-force: the deflection sensitivity is not in the file and is needed to turn the deflection signal (V) into a length (give it: --sensitivity 50nm/V)" check "$v/jpk_calibration.jpk-force"
run_ok check --sensitivity 50nm/V --spring-constant 0.032N/m "$v/jpk_calibration.jpk-force" && \
    has "check calibration with options" "$tmp/out" "sensitivity 50 nm/V (option --sensitivity)"
expect_fail 2 "layerfit: $v/jpk_map.jpk-force-map: no curve 6: the file holds 6 (0..5)" check "$v/jpk_map.jpk-force-map#6"

# fit one curve; a whole map is refused by a single fit
run_ok fit "$v/jpk_map.jpk-force-map#2" --k 2 --R 8um --model halfspace && \
    has "fit map#2: w of its column" "$tmp/out" "w    = 1.25 mJ/m^2"
expect_fail 2 "layerfit: $v/jpk_map.jpk-force-map: holds 6 curves: a fit of one material takes one curve per row: name one as $v/jpk_map.jpk-force-map#0 .. $v/jpk_map.jpk-force-map#5 (or in the plan's index column), or fit each on its own with layerfit fit --batch" fit "$v/jpk_map.jpk-force-map" --k 2 --R 8um --model halfspace

# a batch over a map: one row per curve, its position and grid place
run_ok fit --batch "$v/jpk_map.jpk-force-map" --k 2 --R 8um --model halfspace --out "$tmp/map.csv" --quiet && {
    has "batch map: file#index" "$tmp/map.csv" "$v/jpk_map.jpk-force-map#3,1,ok"
    [ "$(wc -l < "$tmp/map.csv")" -eq 7 ] && ok || bad "batch map: 6 rows and a header"
    row=$(grep -F "jpk_map.jpk-force-map#3," "$tmp/map.csv")
    near "batch map#3: x_m" "$(echo "$row" | cut -d, -f7)" 120e-6 1e-9
    near "batch map#3: w (column 2)" "$(echo "$row" | cut -d, -f9)" 1.25e-3 1e-5
    has "batch map: grid columns" "$tmp/map.csv" ",grid_i,grid_j,sha256"
}
run_ok fit --batch "$v/jpk_map.jpk-force-map" --k 2 --R 8um --model halfspace --out "$tmp/map.jsonl" --quiet && {
    has "batch map jsonl: curve 3's grid place" "$tmp/map.jsonl" '"grid_i": 2, "grid_j": 1'
    has "batch map jsonl: its file" "$tmp/map.jsonl" "jpk_map.jpk-force-map#3"
}
run_ok map "$tmp/map.csv" --plot "$tmp/map.svg" && {
    has "map from the file's grid" "$tmp/map.dat" "120 210 1.25"
    grep -q "3 x 2 map, 6 fits" "$tmp/map.gp" && ok || bad "map: a 3 x 2 grid"
}
run_ok fit --batch "$v/nanoscope_fv.spm" --k 2 --R 8um --model halfspace --out "$tmp/fv.csv" --quiet && \
    [ "$(grep -c ',ok,' "$tmp/fv.csv")" -eq 9 ] && ok || bad "batch force volume: 9 rows ok"
expect_fail 2 "layerfit: fit: $v/jpk_map.jpk-force-map is a curve file, not a plan: state the probe of its curves, e.g. --k 2 --model halfspace (R from the file's header, or --R; --b and --interface for a layer), or --tip sphere, cone, berkovich or pyramid" fit --batch "$v/jpk_map.jpk-force-map"

# plans: FILE#N and the index column; a batch plan row naming a map
printf 'file,k,R,b,interface,index\n%s#0,2,8um,,,\n%s,2,8um,,,2\n' "$v/jpk_map.jpk-force-map" "$v/jpk_qi.jpk-qi-data" > "$tmp/plan.csv"
run_ok check "$tmp/plan.csv" && {
    has "plan check: FILE#0" "$tmp/out" "$v/jpk_map.jpk-force-map#0 (plan line 2)"
    has "plan check: index column" "$tmp/out" "$v/jpk_qi.jpk-qi-data#2 (plan line 3)"
}
run_ok fit "$tmp/plan.csv" --model halfspace && has "joint fit of two map curves" "$tmp/out" "converged"
printf 'file,k,R,b,interface\n%s,2,8um,,\n%s,2,8um,,\n' "$v/jpk_map.jpk-force-map" "$v/igor.ibw" > "$tmp/plan2.csv"
run_ok check "$tmp/plan2.csv" && \
    has "plan check: a map row listed" "$tmp/out" "  curves    6: a fit takes one"
run_ok fit --batch "$tmp/plan2.csv" --model halfspace --out "$tmp/p2.csv" --quiet && \
    [ "$(grep -c ',ok,' "$tmp/p2.csv")" -eq 7 ] && ok || bad "batch plan: the map's 6 curves and the wave"
expect_fail 2 "layerfit: fit: --k is for curve files; a batch of a plan takes each curve's probe and sample from its row (columns k, R, b, interface, tip, half_angle, prefactor, sample)" fit --batch "$tmp/plan2.csv" --k 2

# what a file is when no reader takes it
printf 'hello\n' > "$tmp/notes.txt"
(cd "$tmp" && zip -q notes.zip notes.txt 2>/dev/null) && \
    expect_fail 2 "layerfit: $tmp/notes.zip: a zip archive: layerfit reads JPK archives (.jpk-force, .jpk-force-map, .jpk-qi-data, .jpk-qi-series) and AFM Workshop mapping zips (force-distance CSV files); this one holds 1 file (notes.txt)" check "$tmp/notes.zip"
printf '\211HDF\r\n\032\n\0\0\0\0' > "$tmp/x.h5"
expect_fail 2 "layerfit: $tmp/x.h5: an HDF5 file, which layerfit does not read (export the curves as text, or in the instrument's own format)" check "$tmp/x.h5"

# the real exports, as a user would run them
if [ -d "$real" ]; then
    run_ok check "$real/fmt-jpk-fd_map2x2_extracted.jpk-force-map" && \
        has "real map: listed" "$tmp/out" "  2      571.8 µm    -213.7 µm   9,9        3226    1627, 0, 1599"
    run_ok fit --batch "$real/fmt-jpk-fd_map2x2_extracted.jpk-force-map" --k 2 --R 5um --model halfspace --out "$tmp/real.csv" --quiet
    run_ok map "$tmp/real.csv" --plot "$tmp/real.svg" && \
        grep -q "10 x 10 map, 4 fits" "$tmp/real.gp" && ok || bad "real map: drawn on its 10 x 10 grid"
    for f in "$real"/*.jpk-* "$real"/*.spm "$real"/*.ibw; do
        "$LF" check --sensitivity 50nm/V --spring-constant 0.1N/m "$f" >"$tmp/out" 2>"$tmp/err" && ok || bad "check $f: $(cat "$tmp/err")"
        grep -qi "control byte" "$tmp/err" && bad "check $f: control byte" || ok
    done
else
    echo "skipped: ../shared/realdata not found"
fi
summary
