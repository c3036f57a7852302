#!/bin/sh
# design.sh LAYERFIT: `layerfit design`.  Golden checks of the text, the
# JSON (parsed by python3 where present), the sweep table, the figure, the
# choice, and the messages and exit codes of bad input.
. "$(dirname "$0")/common"

plan=$tmp/plan.csv
cat >"$plan" <<'CSV'
name,k,R_mm,b_um,interface,delta_max_nm,points,baseline,z0,F0
sphere,2,1,1,frictionless,50,120,no,free,free
sphere+baseline,2,1,1,frictionless,50,120,yes,free,free
k3,3,1,1,frictionless,50,120,no,free,free
bonded,2,1,1,bonded,50,120,yes,free,free
CSV

# the whole set, each candidate's contribution, no NaN anywhere
if run_ok design "$plan" --w 10mJ/m2 --E 1GPa --noise 1% --json "$tmp/d.json"; then
    cp "$tmp/out" "$tmp/all.txt"
    has "header" "$tmp/all.txt" "layerfit design: 4 candidates; truth w = 10 mJ/m^2, E* = 1 GPa, nu = 0.3"
    has "candidate line" "$tmp/all.txt" "[2] sphere+baseline: k = 2, R = 1 mm, b = 1 µm, frictionless, unload branch, 120 points"
    has "baseline counted" "$tmp/all.txt" "points past it (baseline)"
    has "no baseline said" "$tmp/all.txt" "0 points past it (no baseline)"
    has "model reason" "$tmp/all.txt" "the thin-layer model"
    has "b/a range" "$tmp/all.txt" "thin-layer validity: b/a"
    has "nu determined by the mixed set" "$tmp/all.txt" "  nu   +- "
    has "contributions" "$tmp/all.txt" "what each candidate adds"
    has "without the bonded curve nu is not fitted" "$tmp/all.txt" "without [4] bonded"
    if grep -qiE "(^|[^a-z])-?nan([^a-z]|$)" "$tmp/all.txt"; then bad "NaN in the text output"; else ok; fi
    if grep -qiE "(^|[^a-z])-?nan([^a-z]|$)" "$tmp/d.json"; then bad "NaN in the JSON"; else ok; fi
    if command -v python3 >/dev/null 2>&1; then
        if python3 - "$tmp/d.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
s = d["set"]
assert s["w"]["determined"] and s["nu"]["free"] and s["nu"]["determined"], s
assert 0 < s["w"]["relative_stderr"] < 1
assert len(s["candidates"]) == 4 and s["candidates"][0]["points_past_detachment"] == 0
assert s["candidates"][1]["points_past_detachment"] > 0
w = {x["row"]: x["set"] for x in d["without"]}
assert w[4]["nu"]["free"] is False and w[4]["nu"]["stderr"] is None
assert d["truth"]["w_J_m2"] == 0.01
PY
        then ok; else bad "JSON content"; fi
    else
        echo "skipped: python3 not found (JSON content not checked)"
    fi
fi

# one k = 2 curve without baseline: w not determined, in words
printf 'k,R,b,interface\n2,1mm,1um,frictionless\n' >"$tmp/k2.csv"
if run_ok design "$tmp/k2.csv" --w 10mJ/m2 --E 1GPa; then
    has "k2 alone: w not determined" "$tmp/out" "  w    not determined: it cannot be told from the force offset"
    has "k2 alone: the fitter's words" "$tmp/out" "k = 2 alone with free F0 and z0 cannot separate w from the force offset"
    has "frictionless: nu" "$tmp/out" "frictionless curves do not depend on nu"
fi
# ... and with the baseline recorded it is
printf 'k,R,b,interface,baseline\n2,1mm,1um,frictionless,yes\n' >"$tmp/k2b.csv"
if run_ok design "$tmp/k2b.csv" --w 10mJ/m2 --E 1GPa; then
    if grep -q "^  w    +- " "$tmp/out"; then ok; else bad "k2 with baseline: w should be determined"; fi
fi
# bonded only: M, not E*
printf 'k,R,b,interface,baseline\n2,1mm,1um,bonded,yes\n3,1mm,1um,bonded,no\n' >"$tmp/bonded.csv"
if run_ok design "$tmp/bonded.csv" --w 10mJ/m2 --E 1GPa --nu 0.35; then
    has "bonded only: E* not determined" "$tmp/out" "  E*   not determined: only M = Z*E* is"
    has "bonded only: M" "$tmp/out" "  M    +- "
fi
if run_ok design "$tmp/bonded.csv" --w 10mJ/m2 --E 1GPa --nu 0.35 --fix-nu; then
    if grep -q "^  E\*   +- " "$tmp/out"; then ok; else bad "bonded with nu held: E* determined"; fi
fi
# absolute noise
if run_ok design "$tmp/k2b.csv" --w 10mJ/m2 --E 1GPa --noise 2uN; then
    has "absolute noise" "$tmp/out" "noise sd 2 µN"
fi

# --choose: greedy, explained, checked against all sets
if run_ok design "$plan" --w 10mJ/m2 --E 1GPa --choose 2 --target w; then
    has "choice header" "$tmp/out" "choice of 2 candidates for w (greedy"
    has "step 1" "$tmp/out" "  step 1: add "
    has "step 2" "$tmp/out" "  step 2: add "
    has "next best" "$tmp/out" "next best: "
    has "exhaustive" "$tmp/out" "(exhaustive search)"
    has "chosen set" "$tmp/out" "the chosen set (predicted standard errors"
fi
if run_ok design "$plan" --w 10mJ/m2 --E 1GPa --choose 3 --target all --json "$tmp/c.json"; then
    has "D-optimal" "$tmp/out" "D-optimal"
    has "json choice" "$tmp/c.json" "\"choice\": {\"target\": \"all\""
fi

# --grid: table, CSV, figure; ranges and units
if run_ok design "$plan" --w 10mJ/m2 --E 1GPa --grid delta_max=20nm:100nm:3 --csv "$tmp/g.csv"; then
    has "sweep table" "$tmp/out" "sweep of delta_max over 3 values (every candidate)"
    has "sweep row" "$tmp/out" "  60 nm "
    near "csv header" "$(csv_field "$tmp/g.csv" 1 1 | sed 's/delta_max_m/1/')" 1 0
    near "csv value 2" "$(csv_field "$tmp/g.csv" 3 1)" 6e-08 1e-12
    if [ "$(wc -l <"$tmp/g.csv")" -eq 4 ]; then ok; else bad "csv: 3 rows and a header"; fi
fi
# a value in um keeps the table's columns (printf pads bytes, the 'µ' is two)
if run_ok design "$plan" --w 10mJ/m2 --E 1GPa --grid b=500nm,1um; then
    cols=$(sed -n '/^  b  /,$p' "$tmp/out" | sed -n '2,3p' \
           | /usr/bin/python3 -c 'import sys; print(" ".join(str(l.rstrip("\n").index(l.split()[2])) for l in sys.stdin))')
    [ "$(echo $cols | cut -d" " -f1)" = "$(echo $cols | cut -d" " -f2)" ] && ok \
        || bad "sweep table: the w column of 500 nm and 1 µm rows at $cols"
fi
if run_ok design "$plan" --w 10mJ/m2 --E 1GPa --grid k=2,2.5,3,4 --vary k3; then
    has "vary one candidate" "$tmp/out" "(candidate [3] k3)"
    has "k row" "$tmp/out" "  2.5 "
fi
if command -v gnuplot >/dev/null 2>&1; then
    if run_ok design "$plan" --w 10mJ/m2 --E 1GPa --grid points=50,100,200 --plot "$tmp/g.svg"; then
        if grep -q "<svg" "$tmp/g.svg"; then ok; else bad "--plot: no SVG written"; fi
        if ls "$tmp" | grep -q "tmp"; then bad "--plot left a temporary file"; else ok; fi
    fi
else
    echo "skipped: gnuplot not found (--plot not checked)"
fi

# bad input: exit 2, one message, nothing on stdout
expect_fail 2 "layerfit: design: --w and --E are required (e.g. --w 10mJ/m2 --E 1GPa)" design "$plan" --w 10mJ/m2
expect_fail 2 "layerfit: design: give one design plan (see 'layerfit design --help')" design --w 10mJ/m2 --E 1GPa
expect_fail 2 "layerfit: design: --noise: 'loud' is not a positive fraction or force (e.g. --noise 1% or --noise 2uN)" design "$plan" --w 10mJ/m2 --E 1GPa --noise loud
expect_fail 2 "layerfit: design: --target must be w, E, nu or all (got 'x')" design "$plan" --w 10mJ/m2 --E 1GPa --choose 1 --target x
expect_fail 2 "layerfit: design: --choose must lie between 1 and the 4 candidates" design "$plan" --w 10mJ/m2 --E 1GPa --choose 5
expect_fail 2 "layerfit: design: --grid: unknown factor 'colour' (k, delta_max, points, b, R or baseline)" design "$plan" --w 10mJ/m2 --E 1GPa --grid colour=1,2
expect_fail 2 "layerfit: design: --grid 'k=2:3': a range is LO:HI:N or LO:HI:N:log" design "$plan" --w 10mJ/m2 --E 1GPa --grid k=2:3
expect_fail 2 "layerfit: design: --plot, --csv and --vary go with --grid" design "$plan" --w 10mJ/m2 --E 1GPa --plot "$tmp/x.svg"
expect_fail 2 "layerfit: design: --plot $tmp/x.pdf: the file must end in .svg or .png" design "$plan" --w 10mJ/m2 --E 1GPa --grid k=2,3 --plot "$tmp/x.pdf"
expect_fail 2 "layerfit: design: output $plan is the input $plan: refusing to replace an input (name another output)" design "$plan" --w 10mJ/m2 --E 1GPa --json "$plan"
expect_fail 2 "layerfit: design: --vary nope: no candidate of that name or number" design "$plan" --w 10mJ/m2 --E 1GPa --grid k=2,3 --vary nope
printf 'k,R,b,interface,colour\n2,1mm,1um,frictionless,red\n' >"$tmp/badcol.csv"
expect_fail 2 "layerfit: $tmp/badcol.csv:1:17: unknown column 'colour' (a design plan has the columns k,R,b,interface and may add name,delta_max,delta_min,points,baseline,z0,F0,segment,noise)" design "$tmp/badcol.csv" --w 10mJ/m2 --E 1GPa
printf 'k,R,b,interface,points\n2,1mm,1um,frictionless,4\n' >"$tmp/badpts.csv"
expect_fail 2 "layerfit: $tmp/badpts.csv:2:24: points must be a whole number from 5 to 10000000" design "$tmp/badpts.csv" --w 10mJ/m2 --E 1GPa
if run_ok design --help; then has "help" "$tmp/out" "usage: layerfit design PLAN.csv"; fi
if "$LF" --help | grep -q "^  design "; then ok; else bad "design missing from layerfit --help"; fi

summary
