# batch_profile.sh: `layerfit fit --batch` makes profile-likelihood
# intervals where the linear ones are unreliable, as a single fit does, and
# writes the interval and its method in every row (CSV and JSON Lines).
. "$(dirname "$0")/common"
PY=/usr/bin/python3

# a synthetic force map: one k = 3 curve per pixel, 80 points, 1% noise;
# w of some pixels has a linear interval the profile does not bear out
"$LF" map --synthetic "$tmp/fm" --size 8 --points 80 --seed 7 2>"$tmp/err"
[ $? -eq 0 ] && ok || bad "map --synthetic: $(cat "$tmp/err")"
run_ok fit --batch "$tmp/fm/plan.csv" --model thin --threads 1 --out "$tmp/b1.csv"
run_ok fit --batch "$tmp/fm/plan.csv" --model thin --threads 2 --out "$tmp/b2.csv"
cmp -s "$tmp/b1.csv" "$tmp/b2.csv" && ok || bad "profiled batch: --threads 1 and 2 give different CSV"
run_ok fit --batch "$tmp/fm/plan.csv" --model thin --threads 1 --out "$tmp/b1.jsonl"
run_ok fit --batch "$tmp/fm/plan.csv" --model thin --threads 2 --out "$tmp/b2.jsonl"
cmp -s "$tmp/b1.jsonl" "$tmp/b2.jsonl" && ok || bad "profiled batch: --threads 1 and 2 give different JSON Lines"
has "CSV header: interval columns" "$tmp/b1.csv" \
    "iterations,w_ci95_lo_J_m2,w_ci95_hi_J_m2,Estar_ci95_lo_Pa,Estar_ci95_hi_Pa,nu_ci95_lo,nu_ci95_hi,w_ci95_method,Estar_ci95_method,nu_ci95_method,identifiability"
has "JSON Lines: the method" "$tmp/b1.jsonl" '"w_ci95_method": "profile likelihood"'

if [ ! -x "$PY" ]; then
    echo "skipped: $PY not found (the row checks)"
else
    # rows: a profiled w holds its estimate, is not the linear interval, and
    # a linear one is exactly w exp(-+1.96 se/w); E* has its interval too
    "$PY" - "$tmp/b1.csv" "$tmp/b1.jsonl" >"$tmp/py" 2>&1 <<'PYEOF'
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
lines = [json.loads(l) for l in open(sys.argv[2])]
prof = lin = 0
bad = []
for r, j in zip(rows, lines):
    if r["status"] != "ok":
        continue
    w, se = float(r["w_J_m2"]), float(r["w_se_J_m2"])
    lo, hi = float(r["w_ci95_lo_J_m2"]), float(r["w_ci95_hi_J_m2"])
    wl, wh = w * math.exp(-1.959963984540054 * se / w), w * math.exp(1.959963984540054 * se / w)
    if j["w_ci95_method"] != r["w_ci95_method"] or j["w_ci95_lo_J_m2"] != lo:
        bad.append("row %s: CSV and JSON differ" % r["fit"])
    if r["w_ci95_method"] == "profile likelihood":
        prof += 1
        if not (lo < w < hi):
            bad.append("row %s: profile interval [%g, %g] misses w = %g" % (r["fit"], lo, hi, w))
        if abs(lo / wl - 1) < 1e-3 and abs(hi / wh - 1) < 1e-3:
            bad.append("row %s: 'profile likelihood' but the linear interval" % r["fit"])
    elif r["w_ci95_method"] == "linear (Wald)":
        lin += 1
        if abs(lo / wl - 1) > 1e-9 or abs(hi / wh - 1) > 1e-9:
            bad.append("row %s: 'linear (Wald)' but not w exp(-+1.96 se/w)" % r["fit"])
    else:
        bad.append("row %s: w's method '%s'" % (r["fit"], r["w_ci95_method"]))
    El, Eh, E = float(r["Estar_ci95_lo_Pa"]), float(r["Estar_ci95_hi_Pa"]), float(r["Estar_Pa"])
    if not (El < E < Eh) or r["Estar_ci95_method"] == "":
        bad.append("row %s: E* interval [%g, %g] of %g" % (r["fit"], El, Eh, E))
    if r["nu_ci95_method"] != "" or r["nu_ci95_lo"] != "":
        bad.append("row %s: nu is held, yet has an interval" % r["fit"])
print("profiled %d linear %d" % (prof, lin))
for b in bad[:5]:
    print("BAD", b)
sys.exit(1 if bad or prof == 0 or lin == 0 else 0)
PYEOF
    [ $? -eq 0 ] && ok || bad "batch rows: $(cat "$tmp/py")"
    # the profiled row carries the interval a single fit of that curve reports
    f=$("$PY" -c 'import csv,sys
for r in csv.DictReader(open(sys.argv[1])):
    if r["w_ci95_method"] == "profile likelihood": print(r["file"]); break' "$tmp/b1.csv")
    { sed -n '/^file,/p' "$tmp/fm/plan.csv"; grep -F "/$(basename "$f")," "$tmp/fm/plan.csv"; } > "$tmp/fm/one.csv"
    run_ok fit "$tmp/fm/one.csv" --model thin --json "$tmp/one.json"
    "$PY" - "$tmp/b1.csv" "$tmp/one.json" "$f" >"$tmp/py" 2>&1 <<'PYEOF'
import csv, json, sys
r = [r for r in csv.DictReader(open(sys.argv[1])) if r["file"] == sys.argv[3]][0]
j = json.load(open(sys.argv[2]))
w = j["parameters"]["w"]
ok = w["ci95_method"] == r["w_ci95_method"] and w["ci95"] == [float(r["w_ci95_lo_J_m2"]), float(r["w_ci95_hi_J_m2"])]
print(w, r["w_ci95_lo_J_m2"], r["w_ci95_hi_J_m2"], r["w_ci95_method"])
sys.exit(0 if ok else 1)
PYEOF
    [ $? -eq 0 ] && ok || bad "a profiled batch row and the single fit of its curve differ: $(cat "$tmp/py")"
fi

# a failed row has empty interval cells
printf 'file,k,R,b,interface\nmissing.csv,2,1mm,1um,frictionless\n' > "$tmp/miss.csv"
"$LF" fit --batch "$tmp/miss.csv" --out "$tmp/miss.out.csv" 2>/dev/null
has "a failed row: empty interval cells" "$tmp/miss.out.csv" ",,,,,,,,,"
# --intervals linear: no check, and every interval says so (the numbers
# themselves are those of the default run)
if [ -x "$PY" ]; then
    run_ok fit --batch "$tmp/fm/plan.csv" --model thin --threads 2 --intervals linear --out "$tmp/lin.csv"
    "$PY" -c 'import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["status"] == "ok"]
m = set(r["w_ci95_method"] for r in rows) - {""}
sys.exit(0 if m == {"linear (Wald), not checked"} else 1)' "$tmp/lin.csv" && ok \
        || bad "--intervals linear: a row's w method is not 'linear (Wald), not checked'"
    cut -d, -f1-21 "$tmp/b1.csv" > "$tmp/a"; cut -d, -f1-21 "$tmp/lin.csv" > "$tmp/b"
    cmp -s "$tmp/a" "$tmp/b" && ok || bad "--intervals linear changes the estimates"
    run_ok fit "$tmp/fm/one.csv" --model thin --intervals linear
    has "single fit: --intervals linear said" "$tmp/out" "(linear, not checked: --intervals linear)"
    expect_fail 2 "layerfit: fit: --intervals must be auto or linear (got 'both')" \
        fit "$tmp/fm/one.csv" --model thin --intervals both
fi
summary
