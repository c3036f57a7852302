# models.sh: `layerfit fit --model auto|thin|exact|halfspace` and
# --model-tol on data made with the exact layer model: which model each
# curve uses and why, the "thin-layer model would give" line, JSON fields,
# and the errors.
. "$(dirname "$0")/common"

# a/b from 0.9 to 10 (k = 2, b = 1 um) and 8 to 55 (k = 3)
run_ok simulate --out "$tmp/x" --model exact --w 10mJ/m2 --E 1GPa --noise 0.005 --seed 3 \
    --z0 15nm k=2,R=1mm,b=1um,interface=frictionless k=3,R=1mm,b=1um,interface=frictionless
# k = 3 on 100 nm: a/b 60-540, the thin model is good enough
run_ok simulate --out "$tmp/t" --model exact --w 10mJ/m2 --E 1GPa --noise 0.001 --seed 4 \
    k=3,R=1mm,b=100nm,interface=frictionless

# auto (the default) on the thick case
run_ok fit "$tmp/x/plan.csv" --json "$tmp/a.json"
has "auto: header" "$tmp/out" "model auto (mixed; 2 fits, tolerance 0.2 se)"
has "auto: k=2 curve exact, with its reason" "$tmp/out" "model exact: the thin-layer model would bias w by"
has "auto: k=3 curve stays thin" "$tmp/out" "model thin: the thin-layer model biases w by at most"
has "auto: thin comparison line" "$tmp/out" "the thin-layer model would give w "
has "json: curve model" "$tmp/a.json" '"model": "exact", "model_reason": "the thin-layer model would bias w by'
has "json: curve model thin" "$tmp/a.json" '"model": "thin", "model_reason": '
has "json: model request" "$tmp/a.json" '"model": "mixed", "model_request": "auto", "model_rounds": 2, "model_tol": 0.2'
has "json: thin comparison" "$tmp/a.json" '"thin_comparison": {'
has "json: thin comparison numbers" "$tmp/a.json" '"w_rel_diff": '
w=$(sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$tmp/a.json" | head -n 1)
wse=$(sed -n 's/.*"w": {"value": [^,]*, "stderr": \([^,]*\),.*/\1/p' "$tmp/a.json" | head -n 1)
near "auto: w within 3 se of the truth" "$w" 0.01 0 "$(awk -v s="$wse" 'BEGIN { print 3 * s }')"

# a tighter tolerance moves the k = 3 curve too
run_ok fit "$tmp/x/plan.csv" --model-tol 0.01
has "tight tolerance: all exact" "$tmp/out" "model auto (exact; "

# exact on request: the comparison is still made
run_ok fit "$tmp/x/plan.csv" --model exact --json "$tmp/e.json"
has "exact: header" "$tmp/out" "model exact, method lm"
has "exact: as requested" "$tmp/out" "model exact: as requested"
has "exact: thin line" "$tmp/out" "the thin-layer model would give w "
has "exact json: model_tol null" "$tmp/e.json" '"model_request": "exact", "model_rounds": 1, "model_tol": null'
w=$(sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$tmp/e.json" | head -n 1)
wse=$(sed -n 's/.*"w": {"value": [^,]*, "stderr": \([^,]*\),.*/\1/p' "$tmp/e.json" | head -n 1)
near "exact: w within 3 se of the truth" "$w" 0.01 0 "$(awk -v s="$wse" 'BEGIN { print 3 * s }')"

# thin on request: no comparison
run_ok fit "$tmp/x/plan.csv" --model thin --json "$tmp/h.json"
has "thin: header" "$tmp/out" "model thin, method lm"
if grep -q "the thin-layer model would give" "$tmp/out"; then bad "thin: no comparison line"; else ok; fi
has "thin json: null comparison" "$tmp/h.json" '"thin_comparison": null'

# halfspace on request runs (on half-space data, joint k = 2 and 3)
run_ok simulate --out "$tmp/s" --model halfspace --w 10mJ/m2 --E 1GPa --noise 0.002 --seed 5 \
    --delta-max 200nm k=2,R=1mm,b=1mm,interface=frictionless k=3,R=1mm,b=1mm,interface=frictionless
run_ok fit "$tmp/s/plan.csv" --model halfspace
has "halfspace: header" "$tmp/out" "model halfspace, method lm"

# auto keeps thin where it is good enough, and says so
run_ok fit "$tmp/t/plan.csv" --json "$tmp/k.json"
has "thin enough: header" "$tmp/out" "model auto (thin; 1 fit, tolerance 0.2 se)"
has "thin enough: reason" "$tmp/out" "model thin: the thin-layer model biases w by at most"
has "thin enough: no comparison" "$tmp/k.json" '"thin_comparison": null'

expect_fail 2 "layerfit: fit: --model-tol must be a number > 0 (e.g. --model-tol 0.2)" fit "$tmp/x/plan.csv" --model-tol 0
expect_fail 2 "layerfit: fit: --model-tol applies to --model auto only" fit "$tmp/x/plan.csv" --model exact --model-tol 0.1
expect_fail 2 "layerfit: fit: unknown model 'thick' (auto, thin, exact, halfspace)" fit "$tmp/x/plan.csv" --model thick
summary
