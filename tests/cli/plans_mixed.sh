#!/bin/sh
# plans_mixed.sh: a plan may list exported files of any supported format,
# mixed (a Chiaro export, a JPK export, a plain CSV curve); a half-space fit
# needs no b and interface (empty cells), any other model refuses such a row
# naming it; the reports say where each curve's R, b and AFM constants came
# from (option, plan, file header).
. "$(dirname "$0")/common"
v=$top/datasets/vendors

# a CSV curve of the same material as the vendor files (datasets/vendors/
# README.md: R = 8 um, w = 1 mJ/m^2, E* = 25 kPa), retract deepest first
"$LF" model --model halfspace --k 2 --R 8um --b 1mm --w 1mJ/m2 --E 25kPa \
    --from -2um --to 3um --points 40 >"$tmp/m.csv" || bad "model: exit $?"
{ head -n 1 "$tmp/m.csv"; tail -n +2 "$tmp/m.csv" | sort -t, -k1,1 -g -r; } >"$tmp/curve.csv"
printf 'file,k,R,b,interface,format\n%s,2,header,,,\n%s,2,8um,,,jpk\ncurve.csv,2,8um,,,\n' \
    "$v/chiaro.txt" "$v/jpk_volts.txt" >"$tmp/plan.csv"

run_ok check "$tmp/plan.csv" && {
    has "check: chiaro row, R from the header, no layer" "$tmp/out" "k = 2, R = 8 µm (file header), b = none, no interface (--model halfspace only)"
    has "check: three formats" "$tmp/out" "  format    chiaro"
    has "check: jpk" "$tmp/out" "  format    jpk"
    has "check: csv" "$tmp/out" "  format    csv"
    has "check: csv columns" "$tmp/out" "depth: column 1 'depth_m' in m (from the header), x 1 to m"
    has "check: csv ignored columns" "$tmp/out" "ignored: column 5 'stable'"
}
run_ok fit "$tmp/plan.csv" --model halfspace --json "$tmp/p.json" && {
    w=$(sed -n 's/.*"w": {"value": \([^,]*\),.*/\1/p' "$tmp/p.json")
    E=$(sed -n 's/.*"Estar": {"value": \([^,]*\),.*/\1/p' "$tmp/p.json")
    near "mixed plan, no b: w (truth 1 mJ/m^2)" "$w" 1e-3 1e-4
    near "mixed plan, no b: E* (truth 25 kPa)" "$E" 25e3 1e-4
    has "report: no layer said" "$tmp/out" "k = 2, R = 8 µm, no layer (half-space), unload branch"
    has "report: chiaro R source" "$tmp/out" "from: R file header, b none (half-space), spring constant 0.032 N/m file header"
    has "report: jpk sources" "$tmp/out" "from: R plan, b none (half-space), spring constant 0.032 N/m file header, sensitivity 50 nm/V file header"
    has "report: csv sources" "$tmp/out" "from: R plan, b none (half-space)"
    if grep -q "the thin-layer model would give" "$tmp/out"; then
        bad "no thin-layer comparison without a layer thickness"; else ok; fi
    if grep -q "b/a = " "$tmp/out"; then bad "no b/a without a layer"; else ok; fi
    has "json: no b/a without a layer" "$tmp/p.json" '"b_over_a_min_contact": null, "b_over_a_pulloff": null'
    has "json: R source" "$tmp/p.json" '"R_source": "file header", "b_source": null, "spring_constant": 0.032, "spring_constant_source": "file header", "sensitivity": null'
    has "json: sensitivity source" "$tmp/p.json" '"sensitivity": 5e-08, "sensitivity_unit": "m/V", "sensitivity_source": "file header"'
    has "json: no layer, b null" "$tmp/p.json" '"R": 8e-06, "b": null'
    if grep -qiw "nan" "$tmp/p.json" "$tmp/out"; then bad "no NaN in the outputs"; else ok; fi
}
run_ok fit --batch "$tmp/plan.csv" --model halfspace --threads 1 --out "$tmp/b.csv" && {
    n=$(grep -c ',ok,' "$tmp/b.csv")
    [ "$n" -eq 3 ] && ok || bad "batch, no b: 3 ok rows (got $n)"
}
# any model but the half-space needs b and interface: the row is named
for m in thin exact auto; do
    expect_fail 2 "layerfit: $tmp/plan.csv:2: b and interface are empty (no layer): only the half-space model needs neither; the model '$m' needs both (give them, or fit with --model halfspace)" fit "$tmp/plan.csv" --model $m
done
expect_fail 2 "layerfit: $tmp/plan.csv:2: b and interface are empty (no layer): only the half-space model needs neither; the model 'thin' needs both (give them, or fit with --model halfspace)" fit --batch "$tmp/plan.csv" --model thin --out "$tmp/t.csv"
[ -e "$tmp/t.csv" ] && bad "refused batch wrote its output" || ok
# b without interface (or the reverse) is a mistake, not a half-space
printf 'file,k,R,b,interface\ncurve.csv,2,8um,1um,\n' >"$tmp/half.csv"
expect_fail 2 "layerfit: $tmp/half.csv:2:21: b and interface go together: give both for a layer, or leave both empty for a half-space (fit with --model halfspace)" check "$tmp/half.csv"
printf 'file,k,R,b,interface\ncurve.csv,2,8um,,bonded\n' >"$tmp/half2.csv"
expect_fail 2 "layerfit: $tmp/half2.csv:2:18: b and interface go together: give both for a layer, or leave both empty for a half-space (fit with --model halfspace)" check "$tmp/half2.csv"

# the single fit: R and the constants from the options are said to be so
run_ok fit "$v/workshop_force.csv" --model halfspace --k 2 --R 8um --spring-constant 0.032N/m --json "$tmp/w.json" --report "$tmp/w.html" && {
    # the page's curve table: no layer thickness (inside, b is only a stand-in)
    row=$(sed -n '/id="curve-table"/,/<\/table>/p' "$tmp/w.html" | grep '<td class="num">1</td>')
    case "$row" in
        *"<td>none</td><td>half-space</td>"*) ok ;;
        *) bad "report: the half-space curve's row shows a layer: $row" ;;
    esac
    has "half-space: nu unseen, said of half-space curves" "$tmp/out" "half-space curves do not depend on nu"
    has "single: option sources" "$tmp/out" "from: R option, b none (half-space), spring constant 0.032 N/m option"
    has "single json: option sources" "$tmp/w.json" '"R_source": "option", "b_source": null, "spring_constant": 0.032, "spring_constant_source": "option"'
}
run_ok fit "$top/datasets/k2_frictionless.csv" --k 2 --R 1mm --b 1um --interface frictionless --model thin --json "$tmp/l.json" && {
    has "single with a layer: sources" "$tmp/out" "from: R option, b option"
    has "single with a layer: b/a said" "$tmp/out" "b/a = "
    has "single json with a layer" "$tmp/l.json" '"R_source": "option", "b_source": "option", "spring_constant": null, "spring_constant_source": null'
}

# AFM Workshop: a constant left at the software's unset default of 1 is said
# to be so, and the option it needs is named
sed 's/^Force Constant, nN\/nm:\t0.032000/Force Constant, nN\/nm:\t1.000000/; s/^Light Lever Gain, mV\/nm:\t2.500000/Light Lever Gain, mV\/nm:\t1.000000/' \
    "$v/workshop_tb.csv" >"$tmp/ws1.csv"
expect_fail 2 "layerfit: $tmp/ws1.csv: the file's 'Force Constant, nN/nm' reads '1.000000', not a calibrated value (1 is the software's unset default), and the cantilever spring constant is needed to convert the signals (give it: --spring-constant 0.032N/m)" check "$tmp/ws1.csv"
expect_fail 2 "layerfit: $tmp/ws1.csv: the file's 'Light Lever Gain, mV/nm' reads '1.000000', not a calibrated value (1 is the software's unset default), and the deflection sensitivity is needed to convert the signals (give it: --sensitivity 50nm/V)" check --spring-constant 0.032N/m "$tmp/ws1.csv"
run_ok check --spring-constant 0.032N/m --sensitivity 400nm/V "$tmp/ws1.csv" && \
    has "workshop unset defaults: the options used" "$tmp/out" "sensitivity 400 nm/V (option --sensitivity)"

# real exports, as exported: a Chiaro and a JPK file in one plan, no layer
real=$top/../shared/realdata
if [ -d "$real" ]; then
    printf 'file,k,R,b,interface,sample\n%s,2,header,,,peg\n%s,2,8um,,,gel\n' \
        "$real/10 wv pc PEGFN S-1 X-1 Y-1 I-1.txt" "$real/force-save-2021.06.30-13.48.08.425.txt" \
        >"$tmp/real.csv"
    run_ok check "$tmp/real.csv" && {
        has "real: chiaro found" "$tmp/out" "  format    chiaro"
        has "real: jpk found" "$tmp/out" "  format    jpk"
    }
    run_ok fit --batch "$tmp/real.csv" --model halfspace --threads 1 --out "$tmp/real.jsonl" && {
        n=$(grep -c '"status": "ok"' "$tmp/real.jsonl")
        [ "$n" -eq 2 ] && ok || bad "real batch: two ok fits (got $n)"
        if grep -qiw "nan" "$tmp/real.jsonl"; then bad "real batch: no NaN"; else ok; fi
    }
    printf 'file,k,R,b,interface\n%s,2,header,,\n' "$real/10 wv pc PEGFN S-1 X-1 Y-1 I-1.txt" >"$tmp/peg.csv"
    run_ok fit "$tmp/peg.csv" --model halfspace --json "$tmp/peg.json" && {
        has "real: R from the header, said" "$tmp/out" "from: R file header, b none (half-space), spring constant 0.032 N/m file header"
        has "real json: sources" "$tmp/peg.json" '"R_source": "file header", "b_source": null'
        # a batch row's chi2_dof is the report's chi2/dof (correlated noise:
        # not the standard errors' scale, which also holds the correlation)
        one=$(sed -n 's/.*"chi2": \([^,]*\), "dof": \([0-9]*\).*/\1 \2/p' "$tmp/peg.json")
        run_ok fit --batch "$tmp/peg.csv" --model halfspace --out "$tmp/peg_rows.csv" && {
            row=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "chi2_dof") c = i } NR == 2 { print $c }' "$tmp/peg_rows.csv")
            near "real batch: chi2_dof as the report's" "$row" "$(echo "$one" | awk '{ printf "%.17g", $1 / $2 }')" 1e-9
        }
    }
else
    echo "skipped: ../shared/realdata not found"
fi
summary
