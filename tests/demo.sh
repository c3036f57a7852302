#!/bin/sh
# demo.sh LAYERFIT: the main job on a bundled example (see README): a joint
# fit of three probes on frictionless and bonded layers, then the model.
LF=${1:-build/layerfit}
top=$(cd "$(dirname "$0")/.." && pwd)
out=build/demo
mkdir -p "$out" || exit 1
echo "== Joint fit of datasets/demo (truth: w = 12.3 mJ/m^2, E* = 1.85 GPa, nu = 0.35; see its README)"
"$LF" fit "$top/datasets/demo/plan.csv" --json "$out/fit.json" --curves "$out/fit_curves.csv"
rc=$?
[ $rc -eq 0 ] || [ $rc -eq 3 ] || exit $rc
echo
echo "== Pull-off of power-law probes on a 1 um layer (w = 10 mJ/m^2, E* = 1 GPa, R = 1 mm)"
printf '%-4s %-13s %-14s %-12s %-8s\n' k "P_po [N]" "a_po [m]" "sigma_po [Pa]" "b/a_po"
for k in 1.5 2 2.5 3 4 5; do
    "$LF" model --k $k --R 1mm --b 1um --w 10mJ/m2 --E 1GPa --json > "$out/pulloff_k$k.json" || exit 1
    awk -v k=$k -F': ' '/"P_po_N"/ { p = $2 } /"a_po_m"/ { a = $2 } /"sigma_po_Pa"/ { s = $2 }
        /"b_over_a_po"/ { r = $2 } END { gsub(",", "", p); gsub(",", "", a); gsub(",", "", s); gsub(",", "", r);
        printf "%-4s %-13.6g %-14.5g %-12.4g %-8.3g\n", k, p, a, s, r }' "$out/pulloff_k$k.json"
done
"$LF" model --figure 3 > "$out/figure3.csv" || exit 1
if command -v gnuplot >/dev/null 2>&1; then
    "$LF" model --figure 3 --plot "$out/figure3.svg" > /dev/null || exit 1
fi
echo "output: $out/ (fit.json, fit_curves.csv, figure3.csv$(command -v gnuplot >/dev/null 2>&1 && echo ', figure3.svg'), pulloff_k*.json)"
