# report.sh: `layerfit fit --plot DIR` and `--report FILE.html`; the page is
# loaded in headless Chromium, whose DOM must hold every table and figure
# (tests/cli/browser.sh clicks through it).
. "$(dirname "$0")/common"

"$LF" simulate --out "$tmp/d" --w 12mJ/m2 --E 1.3GPa --noise 0.003 --seed 11 --z0 20nm \
    --points 120 k=2,R=1mm,b=1um,interface=frictionless k=3,R=1mm,b=1um,interface=frictionless \
    >/dev/null 2>"$tmp/err" && ok || bad "simulate: $(cat "$tmp/err")"
if ! "$LF" fit --help | grep -q -- "--report"; then
    echo "note: this build's 'layerfit fit' has no --plot/--report yet"
    summary; exit
fi

# figures: kept scripts and data, PNG and SVG, a script that redraws
if command -v gnuplot >/dev/null 2>&1; then
    run_ok fit "$tmp/d/plan.csv" --plot "$tmp/figs"
    for f in overview curve1 curve2; do
        for e in png svg gp dat; do
            [ -s "$tmp/figs/$f.$e" ] && ok || bad "--plot wrote $f.$e"
        done
    done
    [ "$(head -c 4 "$tmp/figs/curve1.png" | od -An -c | tr -d ' ')" = "211PNG" ] && ok \
        || bad "curve1.png is a PNG"
    has "per-curve figure: stable branch" "$tmp/figs/curve1.gp" "title 'fit, stable'"
    has "per-curve figure: unstable branch dashed" "$tmp/figs/curve1.gp" "dt 2"
    has "per-curve figure: pull-off" "$tmp/figs/curve1.gp" "title 'pull-off"
    has "per-curve figure: residuals" "$tmp/figs/curve1.gp" "ylabel 'residual"
    has "overview: shared axes in nm" "$tmp/figs/overview.gp" "(nm)"
    has "the data say what they hold" "$tmp/figs/curve1.dat" "# index 4: force-controlled pull-off"
    rm "$tmp/figs/curve2.svg"
    (cd "$tmp/figs" && gnuplot curve2.gp) && [ -s "$tmp/figs/curve2.svg" ] && ok \
        || bad "the kept script redraws the figure"
else
    echo "note: gnuplot not installed, figures not tested"
fi

# without gnuplot the fit still works and says how to install it
PATH=/nonexistent "$LF" fit "$tmp/d/plan.csv" --plot "$tmp/nog" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] && ok || bad "fit --plot without gnuplot: exit $rc"
has "fit result still printed" "$tmp/out" "E*   ="
has "how to install gnuplot" "$tmp/err" "apt-get install gnuplot-nox"
[ -s "$tmp/nog/curve1.gp" ] && ok || bad "scripts are written without gnuplot"
# the page needs no gnuplot: it draws its figures itself (page.js)
PATH=/nonexistent "$LF" fit "$tmp/d/plan.csv" --report "$tmp/nog.html" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] && [ ! -s "$tmp/err" ] && ok || bad "fit --report without gnuplot: exit $rc: $(cat "$tmp/err")"

# the page: one file, its script and style inline, the data as JSON that
# no name can break out of (tests/cli/browser.sh loads it in a browser)
run_ok fit "$tmp/d/plan.csv" --report "$tmp/r.html"
has "page has the data" "$tmp/r.html" '<script type="application/json" id="lf-data">{"kind":"fit"'
has "page has the version" "$tmp/r.html" '<meta name="generator" content="layerfit 0.'
has "page has the command line" "$tmp/r.html" "layerfit fit $tmp/d/plan.csv --report $tmp/r.html"
grep -Eq '<(link|img|iframe)|src=|https?:' "$tmp/r.html" && bad "the page loads nothing from elsewhere" || ok
[ "$(grep -c '</script>' "$tmp/r.html")" -eq 2 ] && ok || bad "two script elements, each closed once"
awk '/id="lf-data">/,/<\/script>/' "$tmp/r.html" | sed 's/.*id="lf-data">//; s/<\/script>.*//' >"$tmp/data.json"
if command -v python3 >/dev/null 2>&1; then
    python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); assert len(d["plots"]) == 2 and d["result"]["fit"]["converged"]' \
        "$tmp/data.json" && ok || bad "the page's data are the fit's JSON and its two curves"
fi
expect_fail 2 "layerfit: fit: --report $tmp/r.pdf: the report is a web page, FILE.html" \
    fit "$tmp/d/plan.csv" --report "$tmp/r.pdf"

# a map's page keeps every point near contact and pull-off of a 300-point
# curve, and at most 64: against the fit's page of the same curve (all of
# its points)
if command -v python3 >/dev/null 2>&1; then
    "$LF" map --synthetic "$tmp/m" --size 2 --points 300 --seed 3 >/dev/null 2>&1 && ok || bad "map --synthetic"
    run_ok fit --batch "$tmp/m/plan.csv" --out "$tmp/m.csv" --report "$tmp/m.html" --model thin --quiet
    c1=$(sed -n 2p "$tmp/m.csv" | cut -d, -f3)
    run_ok fit "$c1" --k 3 --R 1mm --b 1um --interface frictionless --model thin --report "$tmp/one.html"
    python3 - "$tmp/m.html" "$tmp/one.html" <<'PY' && ok || bad "the map's page keeps every point near contact and pull-off"
import json, sys
def data(path):
    s = open(path, encoding="utf-8").read()
    a = s.index('id="lf-data">') + len('id="lf-data">')
    return json.loads(s[a:s.index("</script>", a)])
def points(p):
    q, z, f = p["q"], p["z"], p["f"]
    return [(z[0] + (z[1] - z[0]) * a / q, f[0] + (f[1] - f[0]) * b / q) for a, b in zip(p["pz"], p["pf"])]
m = data(sys.argv[1])["fits"][0]["c"][0]
full = points(data(sys.argv[2])["plots"][0])
kept = points(m)
assert len(full) == 300 and len(kept) <= 64, (len(full), len(kept))
zs = [z for z, _ in full]
span = max(zs) - min(zs)
zmin = min(full, key=lambda p: p[1])[0]
fspan = m["f"][1] - m["f"][0]
near = [p for p in full if abs(p[0] - m["z0"]) <= 0.02 * span or abs(p[0] - zmin) <= 0.02 * span]
assert len(near) >= 10, len(near)
for z, F in near:    # within a step of the map's quantization
    assert any(abs(z - a) <= 1.5e-3 * span and abs(F - b) <= 1.5e-3 * fspan for a, b in kept), (z, F)
PY
    # the page of the results alone (`map R.csv --report`) redraws each
    # curve from its file and the row's probe, offsets and material: the
    # same points, model and plan rows as the batch's page; a changed file
    # and a missing one are said, not drawn; a joint fit is said
    has "batch rows: the curve's probe and offsets" "$tmp/m.csv" ",instrument_model,k,R_m,b_m,interface,tip,half_angle_rad,B,segment,z0_m,F0_N,slope_N_m,nu_held"
    run_ok map "$tmp/m.csv" --report "$tmp/mr.html"
    cp -r "$tmp/m" "$tmp/m2"
    sed "s#$tmp/m/#$tmp/m2/#g" "$tmp/m.csv" >"$tmp/m2.csv"
    echo "# changed" >>"$(sed -n 2p "$tmp/m2.csv" | cut -d, -f3)"
    rm "$(sed -n 3p "$tmp/m2.csv" | cut -d, -f3)"
    run_ok map "$tmp/m2.csv" --report "$tmp/m2.html"
    awk -F, 'NR == 1 { print $0 ",sample" } NR > 1 { print $0 ",s1" }' "$tmp/d/plan.csv" >"$tmp/d/joint.csv"
    "$LF" fit --batch "$tmp/d/joint.csv" --out "$tmp/j.csv" --quiet >/dev/null 2>&1
    run_ok map "$tmp/j.csv" --report "$tmp/j.html"
    python3 - "$tmp/m.html" "$tmp/mr.html" "$tmp/m2.html" "$tmp/j.html" <<'PY' && ok || bad "map R.csv --report draws the batch page's curves, notes a changed or missing file"
import json, sys
def data(path):
    s = open(path, encoding="utf-8").read()
    a = s.index('id="lf-data">') + len('id="lf-data">')
    return json.loads(s[a:s.index("</script>", a)])["fits"]
batch, alone, changed, joint = (data(p) for p in sys.argv[1:])
assert len(batch) == 4 and all(f["c"] and "mf" in f["c"][0] for f in batch)
assert alone == batch, [(a == b) for a, b in zip(alone, batch)]
assert changed[0]["c"] == [] and "has changed since it was fitted" in changed[0]["note"], changed[0]
assert changed[1]["c"] == [] and "Not drawn" in changed[1]["note"], changed[1]
assert changed[0]["p"][0][3:] == batch[0]["p"][0][3:]     # still in the exported plan
assert changed[2]["c"] == batch[2]["c"]
assert joint[0]["c"] == [] and "joint fit" in joint[0]["note"], joint
PY
fi

# headless Chromium: the DOM its script builds holds the tables and figures
chrome=$(command -v chromium || command -v chromium-browser || true)
if [ -n "$chrome" ]; then
    prof=$(mktemp -d)
    timeout 120 "$chrome" --headless --no-sandbox --disable-gpu --disable-quic --disable-background-networking \
        --no-first-run --disable-component-update --disable-sync --user-data-dir="$prof" \
        --dump-dom "file://$tmp/r.html" >"$tmp/dom.html" 2>"$tmp/chrome.err"
    rm -rf "$prof"
    [ -s "$tmp/dom.html" ] && ok || bad "chromium --dump-dom gave nothing: $(tail -n 3 "$tmp/chrome.err")"
    for id in parameter-table correlation-table curve-table fit-table; do
        grep -q "<table id=\"$id\"" "$tmp/dom.html" && ok || bad "DOM has table $id"
    done
    n=$(grep -o '<canvas' "$tmp/dom.html" | wc -l); [ "$n" -eq 2 ] && ok || bad "DOM has the overview and the curve's canvas ($n)"
    dups=$(grep -o " id=['\"][^'\"]*['\"]" "$tmp/dom.html" | sort | uniq -d | head -n 3)
    [ -z "$dups" ] && ok || bad "duplicate ids on the page: $dups"
else
    echo "note: chromium is not installed (apt-get install -y chromium); the page was not loaded in a browser"
fi

summary
