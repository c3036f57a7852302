# model.sh: golden tests of `layerfit model` and the top-level usage.
. "$(dirname "$0")/common"

P="--k 3 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa"

# top level
run_ok --version && has "--version" "$tmp/out" "layerfit 0."
run_ok --help && has "--help lists model" "$tmp/out" "model"
run_ok model --help && has "model --help" "$tmp/out" "usage: layerfit model"
"$LF" >/dev/null 2>&1; [ $? -eq 2 ] && ok || bad "no command: exit 2"
expect_fail 2 "layerfit: unknown command 'frobnicate' (see 'layerfit --help')" frobnicate

# pull-off against the seed paper's closed forms (Papangelo, Eq. 12-13, 24-25)
run_ok model $P --json
near "P_po k=3" "$(json_field "$tmp/out" P_po_N)" -3.632281e-03 2e-7
near "a_po k=3" "$(json_field "$tmp/out" a_po_m)" 2.0758e-05 3e-5
run_ok model $P --interface bonded --nu 0.3 --json
near "P_po bonded k=3" "$(json_field "$tmp/out" P_po_N)" -3.757239e-03 2e-7
near "a_po bonded k=3" "$(json_field "$tmp/out" a_po_m)" 2.0067e-05 3e-5
run_ok model --k 2 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa --json --sigma-th 10MPa
near "Hertz limit" "$(json_field "$tmp/out" P_po_N)" -6.283185307179586e-05 1e-12
near "b_cr k=2" "$(json_field "$tmp/out" b_cr_m)" 5e-08 1e-12
has "nu is null for frictionless" "$tmp/out" '"nu": null,'

# units: the same curve whatever the spelling
run_ok model --k 2 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa --points 3 --from -2nm --to 30nm
cp "$tmp/out" "$tmp/a"
run_ok model --k 2 --R 1e-3m --b "1 µm" --w "0.01 N/m" --E 1e9Pa --points 3 --from -0.002um --to 3e-8m
if paste -d, "$tmp/a" "$tmp/out" | awk -F, 'NR > 1 { for (i = 1; i <= 4; i++) {
        d = $i - $(i + 5); if (d < 0) d = -d; m = $i < 0 ? -$i : $i;
        if (d > 1e-14 * m) exit 1 } }'; then ok; else bad "unit spellings give the same curve"; fi
has "CSV header" "$tmp/a" "depth_m,force_N,radius_m,b_over_a,stable"
near "force at 30 nm, k=2" "$(csv_field "$tmp/a" 4 2)" \
    "$(awk 'BEGIN { pi = 3.141592653589793; c = sqrt(2e-6 * 0.01 / 1e9); d1 = 30e-9 + c;
                    printf "%.17g", pi * 1e9 / 1e-6 * 1e-3 * d1 * (d1 - 2 * c) }')" 1e-12
run_ok model $P --points 1 --from -10nm
near "out of contact below -c" "$(csv_field "$tmp/out" 2 2)" 0 0 0
run_ok model $P --branch load --points 2 --from -1nm --to 0nm
near "loading: no contact before 0" "$(csv_field "$tmp/out" 2 2)" 0 0 0
near "loading: jump-in at 0" "$(csv_field "$tmp/out" 3 2)" -0.0031730898038992857 1e-12
run_ok model $P --summary && has "summary" "$tmp/out" "pull-off         delta = -1.491 nm, P = -3.632 mN, a = 20.76 µm"

# usage errors: exact messages, exit 2, no output
expect_fail 2 "layerfit: model: --b: '1' has no unit (e.g. 1um)" model --k 3 --R 1mm --b 1 --w 10mJ/m2 --E 1GPa
expect_fail 2 "layerfit: model: --b: unit 'GPa' is a pressure or modulus, not a length (e.g. 1um)" model --k 3 --R 1mm --b 1GPa --w 10mJ/m2 --E 1GPa
expect_fail 2 "layerfit: model exact: nu must be <= 0.4995 for a bonded layer (got 0.4996)" model --model exact --k 3 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa --interface bonded --nu 0.4996 --summary
expect_fail 2 "layerfit: model exact: nu must be <= 0.4995 for a bonded layer (got 0.4996)" model --model exact --k 3 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa --interface bonded --nu 0.4996
expect_fail 2 "layerfit: model: --w: unknown unit 'mJ/parsec2x' (expected a work of adhesion (energy per area) such as 10mJ/m2)" model $P --w 10mJ/parsec2x
expect_fail 2 "layerfit: model: --E is required (e.g. --E 1GPa)" model --k 3 --R 1mm --b 1um --w 10mJ/m2
expect_fail 2 "layerfit: model: --nu is required for a bonded layer (e.g. --nu 0.3)" model $P --interface bonded
expect_fail 2 "layerfit: model: nu must lie in [0, 0.5) for a bonded layer (got 0.5)" model $P --interface bonded --nu 0.5
expect_fail 2 "layerfit: model: k must be a finite number > 0 (got -1)" model --k -1 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa
expect_fail 2 "layerfit: model: R must be a finite length > 0 (got -0.001 m)" model --k 2 --R -1mm --b 1um --w 10mJ/m2 --E 1GPa
expect_fail 2 "layerfit: model: --interface: unknown interface 'glued' (frictionless or bonded)" model $P --interface glued
expect_fail 2 "layerfit: model: --k: 'two' is not a number (e.g. --k 0.3)" model --k two
expect_fail 2 "layerfit: model: unknown option '--depth' (see 'layerfit model --help')" model $P --depth 3nm
expect_fail 2 "layerfit: model: --points needs a value" model $P --points
expect_fail 2 "layerfit: model: --figure: no figure 7 (the paper's figures 2 to 5, or 6: thin-layer error against a/b)" model --figure 7
expect_fail 2 "layerfit: model: --branch: unknown branch 'up' (unload or load)" model $P --branch up
expect_fail 2 "layerfit: model: --model: unknown model 'fem' (e.g. --model thin)" model $P --model fem
expect_fail 2 "layerfit: model: the range is empty: give --from and --to with --to > --from" model $P --from 5nm --to 1nm

# figures
for n in 2 3 4 5; do
    run_ok model --figure $n && [ "$(wc -l <"$tmp/out")" -gt 100 ] && ok || bad "figure $n has data"
done
run_ok model --figure 4
near "Fig. 4 R/b=1e3 k=3" "$(awk -F, '$1 == 1000 && $2 == 3 { print $3 }' "$tmp/out")" -57.810 1e-4
run_ok model --figure 6
near "Fig. 6 exact/thin P1, k=2 frictionless, a/b=1 (Lebedev-Ufliand reference 2.0093)" \
    "$(awk -F, '$1 == 2 && $2 == "frictionless" && $4 == 1 { print $5 }' "$tmp/out")" 2.0093 1e-4
near "Fig. 6 bonded nu=0.45, a/b=10 (Lebedev-Ufliand reference 0.81)" \
    "$(awk -F, '$3 == 0.45 && $4 == 10 { print $5 }' "$tmp/out")" 0.81 0.01

# other models through the same table
run_ok model --model halfspace --k 2 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa --json
near "half-space sphere pull-off -1.5 pi R w" "$(json_field "$tmp/out" P_po_N)" -4.71238898038469e-05 1e-9
run_ok model --model exact --k 3 --R 1mm --b 100nm --w 10mJ/m2 --E 1GPa --json
cp "$tmp/out" "$tmp/exact.json"
run_ok model --k 3 --R 1mm --b 100nm --w 10mJ/m2 --E 1GPa --json
near "exact tends to thin for b << a (k=3, b/a_po ~ 0.01)" "$(json_field "$tmp/exact.json" P_po_N)" \
    "$(json_field "$tmp/out" P_po_N)" 0.02

if command -v gnuplot >/dev/null 2>&1; then
    run_ok model --figure 3 --plot "$tmp/fig3.svg"
    has "svg drawn" "$tmp/fig3.svg" "<svg"
fi
# the models listed from the model table, cheapest first, with their scope
run_ok model --help
has "help lists thin with its assumption" "$tmp/out" "  thin       thin-layer closed form"
has "help lists exact" "$tmp/out" "  exact      finite-thickness layer"
has "help names the half-space assumption" "$tmp/out" "; assumes b >> a"
# the b << a note belongs to thin-layer models only (b/a at pull-off ~0.5 here)
LAYERFIT_NO_CACHE=1 run_ok model --model exact --k 2 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa --summary
if grep -q "thin-layer assumption" "$tmp/out"; then bad "exact model summary warns about b << a"; else ok; fi
run_ok model --model thin --k 2 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa --summary
has "thin model summary warns about b << a" "$tmp/out" "the thin-layer assumption b << a is strained"
# past b = a the thin-layer model does not apply: said in the summary, and
# on stderr beside the CSV (a k = 0.3 tip on 1 um: b/a = 2878 at pull-off)
run_ok model --k 0.3 --R 5um --b 1um --w 10mJ/m^2 --E 1MPa
has "thin past b = a: warned beside the CSV" "$tmp/err" "layerfit: model: warning: b/a = 2878 at pull-off: the thin-layer model does not apply"
run_ok model --k 0.3 --R 5um --b 1um --w 10mJ/m^2 --E 1MPa --summary
has "thin past b = a: summary" "$tmp/out" "b/a at pull-off  2878  (the thin-layer model does not apply: it assumes b << a"
run_ok model --model thin --k 2 --R 1mm --b 1um --w 10mJ/m2 --E 1GPa
[ -s "$tmp/err" ] && bad "thin at b/a 0.33: warned on stderr: $(cat "$tmp/err")" || ok
# w = 0 (accepted: no adhesion): the ratios over w and over the pull-off
# radius are said to be undefined, never printed as nan, inf or -0
for m in thin exact halfspace; do
    LAYERFIT_NO_CACHE=1 run_ok model --model $m --k 2 --R 1mm --b 1um --w 0J/m2 --E 1GPa \
        --summary --sigma-th 1MPa
    if grep -qiE 'nan|inf|-0 ' "$tmp/out"; then
        bad "model --model $m --w 0 --summary: $(grep -iE 'nan|inf|-0 ' "$tmp/out" | head -2)"
    else ok; fi
    has "model --model $m --w 0: pull-off ratio undefined" "$tmp/out" "P_po/(2 pi R w)  undefined"
done
# a half-space needs no --b and reports no layer
run_ok model --model halfspace --k 2 --R 1mm --w 10mJ/m2 --E 1GPa --summary
has "halfspace summary: no layer" "$tmp/out" "half-space (no layer)"
if grep -q "b/a at pull-off" "$tmp/out"; then bad "halfspace summary gives b/a"; else ok; fi
run_ok model --model halfspace --k 2 --R 1mm --w 10mJ/m2 --E 1GPa --points 5
[ "$(tail -n +2 "$tmp/out" | cut -d, -f4 | tr -d '\n')" = "" ] && ok \
    || bad "halfspace curve: b_over_a not empty: $(sed -n 2p "$tmp/out")"
summary
