# browser.sh: the interactive reports (fit --report, fit --batch --report)
# opened from disk in Debian's chromium, headless, driven by puppeteer-core
# (tests/browser, installed by `make deps`): no console error, a click on a
# pixel shows that fit's curve and numbers (#curve=N), zoom, a curve hidden
# and shown, a selection exported as a plan that refits, the back button,
# and a file name made to break out of the page running nothing.  The
# screenshots stay in BUILD/browser-test/ for a person to look at.
. "$(dirname "$0")/common"

chrome=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$chrome" ]; then
    echo "skipped: chromium not found (make deps installs it: apt-get install chromium)"
    summary; exit
fi
if ! command -v node >/dev/null 2>&1; then
    echo "skipped: node not found (make deps installs it: apt-get install nodejs npm)"
    summary; exit
fi
if [ ! -f "$top/tests/browser/node_modules/puppeteer-core/package.json" ]; then
    bad "puppeteer-core is not installed in tests/browser/node_modules (make deps runs npm ci there)"
    summary; exit
fi
shots=$(cd "$(dirname "$LF")" && pwd)/browser-test
rm -rf "$shots"

# a joint fit of two curves, the first under a name that would close the
# script element and run code if it reached the page unescaped
"$LF" simulate --out "$tmp/d" --w 12mJ/m2 --E 1.3GPa --noise 0.003 --seed 11 --z0 20nm \
    --points 120 k=2,R=1mm,b=1um,interface=frictionless k=3,R=1mm,b=1um,interface=frictionless \
    >/dev/null 2>"$tmp/err" && ok || bad "simulate: $(cat "$tmp/err")"
# (and an ampersand entity and U+2028, a line end to old JavaScript)
evil="a</script><img src=x onerror=window.pwned=1>&amp;$(printf '\342\200\250').csv"
mkdir -p "$tmp/d/a<"
mv "$tmp/d/curve1.csv" "$tmp/d/$evil"
{ head -n 1 "$tmp/d/plan.csv"; printf '"%s"' "$evil"; sed -n '2s/^curve1\.csv//p' "$tmp/d/plan.csv"
  tail -n +3 "$tmp/d/plan.csv"; } >"$tmp/d/evil.csv"
run_ok fit "$tmp/d/evil.csv" --report "$tmp/fit.html"
grep -q '<img' "$tmp/fit.html" && bad "the page holds the name's <img unescaped" || ok
# the page's data: no '<', '>', '&' or U+2028 but as \u escapes
sed -n '/id="lf-data">/,/<\/script>/p' "$tmp/fit.html" | sed '1s/.*id="lf-data">//; $s/<\/script>.*//' \
    | grep -q "[<>&]\|$(printf '\342\200\250')" && bad "the page's JSON holds < > & or U+2028 raw" || ok
# a fit stopped after one iteration: marked as not converged
run_exit 3 fit "$tmp/d/evil.csv" --max-iter 1 --report "$tmp/noconv.html"
# a Chiaro export's retract fitted in a window: its approach greyed, the
# window's ends and the measured adhesion on the figure
run_ok fit "$top/datasets/vendors/chiaro.txt" --model halfspace --k 2 --depth-range 0:80% \
    --report "$tmp/approach.html"
# a synthetic 8 x 8 force map, every fit in one page
"$LF" map --synthetic "$tmp/m" --size 8 --points 80 --seed 7 >/dev/null 2>&1 && ok || bad "map --synthetic"
run_ok fit --batch "$tmp/m/plan.csv" --out "$tmp/r.csv" --report "$tmp/map.html" --model thin \
    --intervals linear --quiet
run_ok map "$tmp/r.csv" --report "$tmp/results.html"
expect_fail 2 "layerfit: fit: --report $tmp/x.html: the page is made from the results; give them as --out FILE.csv" \
    fit --batch "$tmp/m/plan.csv" --report "$tmp/x.html"

(cd "$top/tests/browser" && timeout 120 node report.test.js "$chrome" "$tmp" "$shots") \
    >"$tmp/browser.out" 2>&1; rc=$?
grep "^FAIL" "$tmp/browser.out"
n=$(grep -c '^ok:' "$tmp/browser.out"); m=$(grep -c '^FAIL' "$tmp/browser.out")
pass=$((pass + n)); fail=$((fail + m))
[ "$rc" -eq 0 ] || [ "$m" -gt 0 ] || bad "the browser test stopped (exit $rc): $(tail -n 5 "$tmp/browser.out")"
[ "$n" -ge 30 ] && ok || bad "the browser test ran $n checks: $(tail -n 5 "$tmp/browser.out")"
for s in fit map noconv; do
    [ -s "$shots/$s.png" ] && ok || bad "screenshot $s.png"
done

# the exported plan of the kept curves refits: every curve but the one excluded
if [ -s "$tmp/kept.csv" ]; then
    run_ok fit --batch "$tmp/kept.csv" --out "$tmp/kept-r.csv" --model thin --intervals linear --quiet
    [ "$(($(wc -l <"$tmp/kept-r.csv") - 1))" -eq 63 ] && ok || bad "the kept plan refits 63 curves"
fi

summary
