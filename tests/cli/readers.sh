#!/bin/sh
# readers.sh: instrument exports on the command line: `layerfit check` says
# what it detected, `layerfit fit EXPORT --model halfspace --k 2` fits one
# directly (R from its header), plans mix formats, and missing constants are
# errors that name the option.
. "$(dirname "$0")/common"
v=$top/datasets/vendors

# check: format, columns, conversions, segments
run_ok check "$v/chiaro.txt" && {
    has "check chiaro: format" "$tmp/out" "  format    chiaro"
    has "check chiaro: separation" "$tmp/out" "depth: tip-sample separation = 'Piezo (nm)' - 'Cantilever (nm)'"
    has "check chiaro: R" "$tmp/out" "probe radius 8e-06 m (file header 'Tip radius (um)')"
    has "check chiaro: hold" "$tmp/out" "points    92 (load 39, hold 14 (not fitted), unload 39)"
    has "check chiaro: Latin-1 key as UTF-8" "$tmp/out" "metadata  Max load (µN): 0.050"
    has "check chiaro: clamp warned" "$tmp/err" "column 'Indentation (nm)' is clamped: 32 points"
}
run_ok check "$v/jpk_volts.txt" && {
    has "check jpk: sensitivity" "$tmp/out" "sensitivity 50 nm/V (file header 'sensitivity')"
    has "check jpk: segments" "$tmp/out" "extend 40, pause/hold 12, retract 40 points"
}
# a UTF-8 byte order mark (an editor saved the file) changes no format's
# detection
for f in "$v"/*.txt; do
    printf '\357\273\277' > "$tmp/bom.txt"; cat "$f" >> "$tmp/bom.txt"
    "$LF" check --spring-constant 1N/m --sensitivity 61nm/nA "$f" 2>/dev/null | grep '^  format' > "$tmp/want"
    "$LF" check --spring-constant 1N/m --sensitivity 61nm/nA "$tmp/bom.txt" 2>/dev/null | grep '^  format' > "$tmp/got"
    if [ -s "$tmp/want" ] && cmp -s "$tmp/want" "$tmp/got"; then ok
    else bad "BOM: $(basename "$f"): '$(cat "$tmp/got")', want '$(cat "$tmp/want")'"; fi
done
run_ok check --format text "$v/text_space_comma.txt" && \
    has "check text: decimal comma" "$tmp/out" "table: header on line 4, delimiter spaces, decimal comma"
run_ok check "$v/hysitron.txt" && \
    has "check hysitron: voltage ignored" "$tmp/out" "ignored: column 5 'Load (V)' (a raw signal)"
expect_fail 2 "layerfit: $v/ntmdt.txt: the cantilever spring constant is not in the file and is needed to turn the deflection into a force (give it: --spring-constant 0.032N/m)" check "$v/ntmdt.txt"
expect_fail 2 "layerfit: $v/ntmdt.txt: the deflection sensitivity is not in the file and is needed to turn the deflection signal (A) into a length (give it: --sensitivity 61nm/nA)" check --spring-constant 1N/m "$v/ntmdt.txt"
run_ok check --spring-constant 1N/m --sensitivity 61nm/nA "$v/ntmdt.txt" && \
    has "check ntmdt: option named as the source" "$tmp/out" "spring constant 1 N/m (option --spring-constant)"
expect_fail 2 "layerfit: check: --spring-constant: 'abc' does not start with a number (e.g. 0.032N/m)" check --spring-constant abc "$v/ntmdt.txt"
expect_fail 2 "layerfit: $v/chiaro.txt: unknown format 'zeiss' (one of: csv, chiaro, jpk, workshop, ntmdt, hysitron, text, tab, jpk-force, workshop-map, nanoscope, igor)" check --format zeiss "$v/chiaro.txt"
expect_fail 2 "layerfit: $v/jpk_force.txt:12:1: a row of numbers before any row naming the columns (expected a header such as 'Depth (nm)<TAB>Load (uN)' just above the data)" check --format hysitron "$v/jpk_force.txt"
expect_fail 2 "layerfit: $v/hysitron.txt:4: Chiaro table without a depth (expected Load (uN) or Cantilever (nm), and Piezo (nm) with Cantilever (nm), or Indentation (nm))" check --format chiaro "$v/hysitron.txt"

(cat "$v/jpk_force.txt"; tail -n +3 "$v/jpk_force.txt") >"$tmp/two.txt"
expect_fail 2 "layerfit: $tmp/two.txt:127: a second curve begins here (segmentIndex 0 again): one curve per file (export the curves of a force map one by one)" check "$tmp/two.txt"

# fit an export directly: R from the header, no --b for a half-space
run_ok fit "$v/chiaro.txt" --model halfspace --k 2 --json "$tmp/c.json" && {
    has "fit chiaro: R from the header" "$tmp/out" "chiaro.txt: R = 8 µm from the file header (chiaro export)"
    has "fit chiaro: b not used" "$tmp/out" "half-space model: no layer thickness or interface used"
    w=$(sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$tmp/c.json")
    E=$(sed -n 's/.*"Estar": {"value": \([^,]*\),.*/\1/p' "$tmp/c.json")
    near "fit chiaro: w (truth 1 mJ/m^2)" "$w" 1e-3 1e-4
    near "fit chiaro: E* (truth 25 kPa)" "$E" 25e3 1e-4
}
expect_fail 2 "layerfit: fit: $v/text_space_comma.txt: no probe radius: the file states none (give --R, e.g. --R 8um)" fit "$v/text_space_comma.txt" --model halfspace --k 2
run_ok fit "$v/workshop_force.csv" --model halfspace --k 2 --R 8um --spring-constant 0.032N/m --json "$tmp/w.json" && {
    w=$(sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$tmp/w.json")
    near "fit workshop with --spring-constant: w" "$w" 1e-3 1e-4
}

# a plan of mixed formats, one sniffed, two named
run_ok fit "$v/plan.csv" --model halfspace --json "$tmp/p.json" && {
    w=$(sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$tmp/p.json")
    E=$(sed -n 's/.*"Estar": {"value": \([^,]*\),.*/\1/p' "$tmp/p.json")
    near "mixed plan: w" "$w" 1e-3 1e-4
    near "mixed plan: E*" "$E" 25e3 1e-4
}
printf 'file,k,R,b,interface,format\nchiaro.txt,2,8um,8um,frictionless,bruker\n' >"$tmp/badplan.csv"
cp "$v/chiaro.txt" "$tmp/"
expect_fail 2 "layerfit: $tmp/badplan.csv:2:35: unknown format 'bruker' (csv, chiaro, jpk, workshop, ntmdt, hysitron, text, tab, jpk-force, workshop-map, nanoscope, igor; or empty to detect it)" check "$tmp/badplan.csv"

# R from the curve file's header in a plan
printf 'file,k,R,b,interface,format\n%s,2,header,8um,frictionless,\n%s,2,8um,8um,frictionless,jpk\n' \
    "$v/chiaro.txt" "$v/jpk_volts.txt" >"$tmp/hplan.csv"
run_ok check "$tmp/hplan.csv" && \
    has "plan R header: check shows it" "$tmp/out" "k = 2, R = 8 µm (file header), b = 8 µm"
run_ok fit "$tmp/hplan.csv" --model halfspace --json "$tmp/h.json" && {
    has "plan R header: fit says it" "$tmp/out" "chiaro.txt: R = 8 µm from the file header (chiaro export)"
    w=$(sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$tmp/h.json")
    near "plan R header: w" "$w" 1e-3 1e-4
}
printf 'file,k,R,b,interface\n%s,2,header,8um,frictionless\n' "$v/jpk_volts.txt" >"$tmp/hplan2.csv"
expect_fail 2 "layerfit: $tmp/hplan2.csv:2: R 'header', but $v/jpk_volts.txt states no probe radius (give R in the plan)" check "$tmp/hplan2.csv"
expect_fail 2 "layerfit: $tmp/hplan2.csv:2: $v/jpk_volts.txt: no probe radius: the plan's row says R = header and the file states none (give the radius in the plan's R column, e.g. R_um 8)" fit "$tmp/hplan2.csv" --model halfspace
# a plan's probes are its rows': the single-curve options are refused, not ignored
for o in "--R 8um" "--b 1um" "--interface bonded"; do
    # shellcheck disable=SC2086
    expect_fail 2 "layerfit: fit: --$(echo $o | sed 's/--\([a-zA-Z]*\).*/\1/') applies to curve files; $tmp/hplan2.csv is a plan, which gives each curve's probe in its row (columns k, R, b, interface, tip, half_angle, prefactor; R may read 'header'): fit it without the probe options" fit "$tmp/hplan2.csv" --model halfspace $o
done

# batch fits read exports too
run_ok fit --batch "$v/plan.csv" --model halfspace --threads 1 --out "$tmp/b.csv" && \
    has "batch: three ok rows" "$tmp/b.csv" ",ok,"

summary
