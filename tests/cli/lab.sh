#!/bin/sh
# lab.sh: what a lab states and reads off (issue 37).  Curve files named on
# the command line with one probe for all (fit FILE..., fit --batch
# FILE..., --sample, --group-by); a failing batch's reasons on stderr;
# probe shapes stated as labs state them (--tip, --half-angle, --B; a
# k = 1 probe by R refused); the model-free observables in the report, the
# JSON and batch rows; fit windows; the segment words; plan columns.
. "$(dirname "$0")/common"
d=$top/datasets
real=$top/../shared/realdata

# ---- a failing batch says its most common reasons, with counts
"$LF" fit --batch "$d/k2_frictionless.csv" "$d/k3_frictionless.csv" "$d/vendors/chiaro.txt" \
    --k 2 --model halfspace --out "$tmp/f.csv" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ $rc -eq 3 ] && ok || bad "failing batch: exit $rc, want 3"
has "failing batch: count" "$tmp/err" "2 of 3 fits failed"
has "failing batch: the reason counted" "$tmp/err" "  2 fits: $d/k2_frictionless.csv: no probe radius: the file states none (give --R, e.g. --R 8um) (and 1 more like it)"
has "batch of files: the chiaro file fitted" "$tmp/f.csv" "$d/vendors/chiaro.txt,1,ok,halfspace"
has "batch rows: observables columns" "$tmp/f.csv" ",sha256,adhesion_force_N,detachment_work_J,contact_point_m,max_indentation_m,max_force_N,instrument_Eeff_Pa,instrument_model"

# ---- probe statements and what is missing
expect_fail 2 "layerfit: fit: --tip cone needs its half-angle (e.g. --half-angle 35deg)" fit "$d/vendors/chiaro.txt" --tip cone --model halfspace
expect_fail 2 "layerfit: fit: --half-angle states a cone or a four-sided pyramid (--tip cone, --tip pyramid); a Berkovich tip has its own equivalent cone (70.3 deg): leave it out" fit "$d/vendors/chiaro.txt" --tip berkovich --half-angle 65deg --model halfspace
expect_fail 2 "layerfit: fit: --R and --B both state the profile (B = 1/(k R^(k-1))): give one" fit "$d/vendors/chiaro.txt" --k 1.5 --R 1um --B 2 --model halfspace
expect_fail 2 "layerfit: fit: --tip sphere is k = 2: leave --k out (got --k 3)" fit "$d/vendors/chiaro.txt" --tip sphere --k 3 --model halfspace
expect_fail 2 "layerfit: fit: --half-angle: '35' has no unit (e.g. 35deg)" fit "$d/vendors/chiaro.txt" --half-angle 35 --model halfspace
expect_fail 2 "layerfit: fit: --interface needs --b (the layer's thickness, e.g. --b 1um)" fit "$d/vendors/chiaro.txt" --k 2 --interface bonded
run_ok fit "$d/vendors/chiaro.txt" --tip sphere --model halfspace --json "$tmp/s.json" && {
    has "sphere: the report names it" "$tmp/out" ": sphere, R = 8 µm, no layer (half-space)"
    has "sphere: JSON tip" "$tmp/s.json" '"tip": "sphere"'
    has "sphere: R from the header" "$tmp/out" "R = 8 µm from the file header"
}
run_ok fit "$d/vendors/chiaro.txt" --half-angle 70deg --model halfspace --json "$tmp/c.json" && {
    has "a half-angle alone: a cone" "$tmp/out" ": cone, half-angle 70°, no layer"
    has "cone: JSON tip" "$tmp/c.json" '"tip": "cone"'
    has "cone: no R" "$tmp/c.json" '"R": null'
    has "cone: R not used" "$tmp/out" "from: R not used"
}

# ---- layerfit model states its probe the same way
expect_fail 2 "layerfit: model: k = 1 is a cone, and R does not shape a cone (f = r whatever R): state its half-angle (--half-angle 35deg, --tip berkovich, or --tip pyramid --half-angle THETA of its faces) or its prefactor --B (f = B r)" model --k 1 --R 1um --b 1um --w 10mJ/m2 --E 1GPa
run_ok model --model halfspace --tip berkovich --w 10mJ/m2 --E 1GPa --summary && \
    has "model: a Berkovich tip" "$tmp/out" "probe            Berkovich tip as its equivalent cone, half-angle 70.3°, half-space"
run_ok model --model halfspace --half-angle 35deg --w 10mJ/m2 --E 1GPa --json && \
    has "model JSON: the cone" "$tmp/out" '"tip": "cone"'

# ---- segment words: retract is unload, approach is load
w_of() { sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$1" | head -n 1; }
run_ok fit "$d/plan.csv" --segment retract --json "$tmp/r1.json" && \
    run_ok fit "$d/plan.csv" --segment unload --json "$tmp/r2.json" && {
    a=$(w_of "$tmp/r1.json"); b=$(w_of "$tmp/r2.json")
    [ -n "$a" ] && [ "$a" = "$b" ] && ok || bad "--segment retract fits as unload: $a, $b"
}
expect_fail 2 "layerfit: fit: --segment pause is a hold, which is never fitted (unload, retract or withdraw; load, approach or extend)" fit "$d/plan.csv" --segment pause

# ---- plan columns: tip, half_angle, prefactor, depth_range
printf 'file,k,R,b,interface,tip,half_angle,prefactor,depth_range\n%s,,,,,cone,35deg,,:80%%\n%s,1.5,,,,,,2000,\n' \
    "$d/vendors/chiaro.txt" "$d/vendors/jpk_volts.txt" >"$tmp/shapes.csv"
run_ok check "$tmp/shapes.csv" && {
    has "plan: a cone row" "$tmp/out" "probe     cone, half-angle 35°, b = none"
    has "plan: a prefactor row" "$tmp/out" "probe     k = 1.5, B = 2000 m^-0.5 (f = B r^k), b = none"
}
chiaro=$d/vendors/chiaro.txt
kcol=$((${#chiaro} + 2))      # the k cell's column: after the file's name and a comma
printf 'file,k,R,b,interface,tip,half_angle\n%s,2,,,,cone,35deg\n' "$chiaro" >"$tmp/bad.csv"
expect_fail 2 "layerfit: $tmp/bad.csv:2:$kcol: k 2, but a cone is k = 1 (leave k empty)" check "$tmp/bad.csv"
printf 'file,k,R,b,interface\n%s,1,8um,,\n' "$chiaro" >"$tmp/bad.csv"
expect_fail 2 "layerfit: $tmp/bad.csv:2:$kcol: k = 1 is a cone, and R does not shape a cone (f = r whatever R): state its half-angle (a cone: tip cone, half-angle 35deg; tip berkovich; tip pyramid with its face half-angle) or its prefactor B of f = B r" check "$tmp/bad.csv"
printf 'file,k,R,b,interface,depth_range\n%s,2,8um,,,0:30\n' "$chiaro" >"$tmp/bad.csv"
expect_fail 2 "layerfit: $tmp/bad.csv:2:$((kcol + 8)): depth_range: '30' has no unit (e.g. 1um)" check "$tmp/bad.csv"

if [ ! -d "$real" ]; then
    echo "skipped: ../shared/realdata not found"
    summary; exit
fi
peg1="$real/10 wv pc PEGFN S-1 X-1 Y-1 I-1.txt"
peg2="$real/10 wv pc PEGFN S-1 X-1 Y-2 I-1.txt"

# ---- fit *.txt on the PEG exports is the hand-written plan's fit
run_ok fit "$real"/10*.txt --k 2 --model halfspace --json "$tmp/glob.json" && {
    has "glob: two curves" "$tmp/out" "layerfit fit: 2 curves, model halfspace"
    has "glob: R from each header" "$tmp/out" "$peg2: R = 8 µm from the file header"
}
printf 'file,k,R,b,interface\n"%s",2,header,,\n"%s",2,header,,\n' "$peg1" "$peg2" >"$tmp/peg.csv"
run_ok fit "$tmp/peg.csv" --model halfspace --json "$tmp/plan.json"
for key in w Estar; do
    g=$(sed -n "s/.*\"$key\": {\"value\": \([^,]*\),.*/\1/p" "$tmp/glob.json")
    p=$(sed -n "s/.*\"$key\": {\"value\": \([^,]*\),.*/\1/p" "$tmp/plan.json")
    [ -n "$g" ] && [ "$g" = "$p" ] && ok || bad "fit *.txt: $key $g, the plan's $p"
done

# ---- samples: one by a name pattern, two refused for a joint fit
run_ok fit --batch "$real"/10*.txt --k 2 --model halfspace --group-by 'name:^(.*) X-' \
    --out "$tmp/g.csv" --quiet && {
    [ "$(wc -l < "$tmp/g.csv")" -eq 2 ] && ok || bad "group-by: one sample, one row"
    has "group-by: the sample and both curves" "$tmp/g.csv" "1,10 wv pc PEGFN S-1,"
    g=$(csv_field "$tmp/g.csv" 2 9)
    p=$(sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$tmp/plan.json")
    near "group-by: w as the joint fit" "$g" "$p" 1e-12
}
run_ok fit --batch "$real"/10*.txt --k 2 --model halfspace --sample PEG10 \
    --out "$tmp/s.csv" --quiet && {
    [ "$(wc -l < "$tmp/s.csv")" -eq 2 ] && ok || bad "--sample: one sample, one row"
    has "--sample: its name and both curves" "$tmp/s.csv" "1,PEG10,$peg1;$peg2,2,ok,"
    p=$(sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$tmp/plan.json")
    near "--sample: w as the joint fit" "$(csv_field "$tmp/s.csv" 2 9)" "$p" 1e-12
}
expect_fail 2 "layerfit: fit: --sample names one sample for all the files, --group-by forms several: give one" fit "$real"/10*.txt --k 2 --model halfspace --sample PEG10 --group-by dir
run_ok fit --batch "$real"/10*.txt --k 2 --model halfspace --group-by 'name:Y-([0-9])' \
    --out "$tmp/g2.csv" --quiet && {
    [ "$(wc -l < "$tmp/g2.csv")" -eq 3 ] && ok || bad "group-by Y: two samples, two rows"
}
expect_fail 2 "layerfit: fit: the files form several samples ('1', '2', ...): a joint fit is of one material; fit each sample on its own with layerfit fit --batch FILE... --group-by ..." fit "$real"/10*.txt --k 2 --model halfspace --group-by 'name:Y-([0-9])'
expect_fail 2 "layerfit: fit: --group-by: $peg1: its header has no field 'Operator' to group by (layerfit check lists its fields)" fit "$real"/10*.txt --k 2 --model halfspace --group-by field:Operator
run_ok fit --batch "$real"/10*.txt --k 2 --model halfspace --group-by 'field:k (N/m)' --out "$tmp/g3.csv" --quiet && \
    has "group-by a header field" "$tmp/g3.csv" "1,0.032,"

# ---- observables beside the model's pull-off, and the instrument's own result
run_ok fit "$peg1" --k 2 --model halfspace --json "$tmp/o.json" && {
    has "report: measured adhesion" "$tmp/out" "measured (no model): adhesion force 39.27 nN (the model's pull-off"
    has "report: instrument's E[eff]" "$tmp/out" "instrument's own result (header): E[eff] 26.57 kPa (its model not stated)"
    a=$(sed -n 's/.*"adhesion_force_N": \([^,]*\),.*/\1/p' "$tmp/o.json")
    near "JSON: adhesion force about 41 nN" "$a" 41e-9 0.1
    has "JSON: instrument E[eff]" "$tmp/o.json" '"instrument_Eeff_Pa": 26567.836'
    for key in detachment_work_J contact_point_m max_indentation_m max_force_N; do
        has "JSON: $key" "$tmp/o.json" "\"$key\": "
    done
}

# ---- a fit window, said in the report and the JSON
run_ok fit "$peg1" --k 2 --model halfspace --depth-range :50% --json "$tmp/win.json" && {
    has "window: the report" "$tmp/out" "fit window: indentation up to 50% of 641.4 nm past the contact point 8.032 µm"
    has "window: JSON" "$tmp/win.json" '"window": {"depth_range": {"lo": null, "hi": 0.5, "relative": true}'
}

# ---- a Berkovich tip on steel: a k = 1 probe by R refused, saying how to state it
expect_fail 2 "layerfit: fit: k = 1 is a cone, and R does not shape a cone (f = r whatever R): state its half-angle (--half-angle 35deg, --tip berkovich, or --tip pyramid --half-angle THETA of its faces) or its prefactor --B (f = B r)" fit "$real/RobinSteel0000LC.txt" --model halfspace --k 1 --R 5um
run_ok fit "$real/RobinSteel0000LC.txt" --model halfspace --tip berkovich && \
    has "Berkovich: the report" "$tmp/out" "Berkovich tip as its equivalent cone, half-angle 70.3°"
summary
