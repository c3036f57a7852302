# batch.sh: `layerfit fit --batch`, shards, the force-map generator and
# `layerfit map`.
. "$(dirname "$0")/common"

# an 8 x 8 force map, every curve its own fit
"$LF" map --synthetic "$tmp/fm" --size 8 --points 80 --seed 7 2>"$tmp/err"
[ $? -eq 0 ] && ok || bad "map --synthetic: $(cat "$tmp/err")"
has "generator says what it wrote" "$tmp/err" "wrote 64 curves"
n=$(ls "$tmp/fm/curves" | wc -l); [ "$n" -eq 64 ] && ok || bad "64 curve files, got $n"
has "curve has its position" "$tmp/fm/curves/x03_y05.csv" "# x: 3 um"
has "curve has its truth" "$tmp/fm/curves/x03_y05.csv" "# true_w: 0.01 J/m2"

# the same data whatever the generator's subset
"$LF" map --synthetic "$tmp/fm2" --size 8 --every 4 --points 80 --seed 7 2>/dev/null
cmp -s "$tmp/fm/curves/x04_y04.csv" "$tmp/fm2/curves/x04_y04.csv" && ok \
    || bad "a subset holds the same curves as the full map"
[ "$(ls "$tmp/fm2/curves" | wc -l)" -eq 4 ] && ok || bad "--every 4 of 8 x 8 gives 4 curves"

# threads: bitwise the same output
run_ok fit --batch "$tmp/fm/plan.csv" --threads 1 --out "$tmp/r1.csv"
[ -s "$tmp/err" ] && bad "a clean batch is silent on stderr when it is not a terminal: $(cat "$tmp/err")" || ok
run_ok fit --batch "$tmp/fm/plan.csv" --threads 2 --out "$tmp/r2.csv"
cmp -s "$tmp/r1.csv" "$tmp/r2.csv" && ok || bad "--threads 1 and 2 give different CSV"
run_ok fit --batch "$tmp/fm/plan.csv" --threads 1 --out "$tmp/r1.jsonl"
run_ok fit --batch "$tmp/fm/plan.csv" --threads 2 --out "$tmp/r2.jsonl"
cmp -s "$tmp/r1.jsonl" "$tmp/r2.jsonl" && ok || bad "--threads 1 and 2 give different JSON Lines"
[ "$(wc -l < "$tmp/r1.csv")" -eq 65 ] && ok || bad "header + 64 rows"
[ "$(wc -l < "$tmp/r1.jsonl")" -eq 64 ] && ok || bad "64 JSON lines"
has "CSV header" "$tmp/r1.csv" "fit,sample,file,curves,status,model,x_m,y_m,w_J_m2,w_se_J_m2"
# the model is auto by default, as for a single fit; thin on request
run_ok fit --batch "$tmp/fm/plan.csv" --model thin --threads 2 --out "$tmp/thin.csv"
has "thin model on request in a batch" "$tmp/thin.csv" ",ok,thin,"
run_ok fit --batch "$tmp/fm/plan.csv" --model auto --threads 2 --out "$tmp/r3.csv"
cmp -s "$tmp/r1.csv" "$tmp/r3.csv" && ok || bad "a batch's default model is auto, as a single fit's"
has "JSON null for NaN" "$tmp/r1.jsonl" '"nu": null'
# --model auto: each fit chooses its models like a single fit, and says which
run_ok fit --batch "$top/datasets/plan.csv" --model auto --threads 2 --out "$tmp/auto.csv"
"$LF" fit "$top/datasets/plan.csv" --json "$tmp/auto.json" >/dev/null 2>&1
m=$(grep -o '"model": "[a-z]*"' "$tmp/auto.json" | head -n 1 | cut -d'"' -f4)
[ -n "$m" ] && has "batch --model auto names the model a single auto fit chose ($m)" "$tmp/auto.csv" ",ok,$m," \
    || bad "single fit JSON has a model"
# stdout when no --out
run_ok fit --batch "$tmp/fm/plan.csv" --threads 2
cmp -s "$tmp/out" "$tmp/r1.csv" && ok || bad "CSV on stdout equals --out FILE.csv"

# fitted against the truth written into each curve (1% noise: w within 20%,
# E* within 3%); the disc of high w is centred at (40, 24) pitches, so every
# pixel of an 8 x 8 map has w = 10 mJ/m^2.
col() { head -n 1 "$1" | tr ',' '\n' | grep -n -x "$2" | cut -d: -f1; }
cw=$(col "$tmp/r1.csv" w_J_m2); cE=$(col "$tmp/r1.csv" Estar_Pa); cs=$(col "$tmp/r1.csv" status)
row=$(grep -n "x03_y05.csv" "$tmp/r1.csv" | cut -d: -f1)
near "w of pixel (3,5)" "$(csv_field "$tmp/r1.csv" "$row" "$cw")" 0.01 0.2
near "E* of pixel (3,5)" "$(csv_field "$tmp/r1.csv" "$row" "$cE")" \
    "$(awk 'BEGIN { printf "%.17g", 0.5e9 + 1e9 * 3 / 63 }')" 0.03
nok=$(awk -F, -v c="$cs" 'NR > 1 && $c == "ok"' "$tmp/r1.csv" | wc -l)
[ "$nok" -ge 62 ] && ok || bad "at least 62 of 64 fits ok, got $nok"
# the mean of w over the map recovers 10 mJ/m^2 to 3%
near "mean w over the map" "$(awk -F, -v c="$cw" -v s="$cs" 'NR > 1 && $s == "ok" { t += $c; n++ }
    END { printf "%.17g", t / n }' "$tmp/r1.csv")" 0.01 0.03

# shards: in order, one header kept, they make the whole
for i in 1 2 3; do
    run_ok fit --batch "$tmp/fm/plan.csv" --shard $i/3 --out "$tmp/s$i.csv"
    run_ok fit --batch "$tmp/fm/plan.csv" --shard $i/3 --out "$tmp/s$i.jsonl"
done
{ cat "$tmp/s1.csv"; tail -n +2 "$tmp/s2.csv"; tail -n +2 "$tmp/s3.csv"; } > "$tmp/merged.csv"
cmp -s "$tmp/merged.csv" "$tmp/r1.csv" && ok || bad "CSV shards 1..3 merged differ from the whole"
cat "$tmp/s1.jsonl" "$tmp/s2.jsonl" "$tmp/s3.jsonl" > "$tmp/merged.jsonl"
cmp -s "$tmp/merged.jsonl" "$tmp/r1.jsonl" && ok || bad "JSONL shards merged differ from the whole"
[ "$(wc -l < "$tmp/s1.csv")" -eq 22 ] && ok || bad "shard 1/3 of 64 holds 21 fits"
run_ok fit --batch "$tmp/fm/plan.csv" --shard 1/70 --out "$tmp/empty.csv"
[ "$(wc -l < "$tmp/empty.csv")" -eq 1 ] && ok || bad "a share with no fit is a header"

# --model auto once per probe and layer: the first 8 fits of a group choose
# by their own rule, the others with their group where its margin settles
# it; every answer is the per-curve rule's (--model-each), with threads and
# in shards alike
"$LF" map --synthetic "$tmp/fg" --size 5 --points 300 --seed 7 2>/dev/null
run_ok fit --batch "$tmp/fg/plan.csv" --threads 2 --out "$tmp/g.csv"
run_ok fit --batch "$tmp/fg/plan.csv" --threads 2 --model-each --out "$tmp/e.csv"
[ "$(head -n 1 "$tmp/g.csv" | tr ',' '\n' | tail -n 1)" = model_by ] && ok || bad "model_by is the last column"
ng=$(awk -F, 'NR > 1 && $NF == "group"' "$tmp/g.csv" | wc -l)
[ "$ng" -ge 1 ] && ok || bad "some fits of the 5 x 5 map decided with their group, got $ng"
[ "$(awk -F, 'NR > 1 && NR <= 9 && $NF == "curve"' "$tmp/g.csv" | wc -l)" -eq 8 ] && ok \
    || bad "the group's first 8 fits decide by their own rule"
[ "$(awk -F, 'NR > 1 && $NF != "curve"' "$tmp/e.csv" | wc -l)" -eq 0 ] && ok \
    || bad "--model-each: every fit decides by its own rule"
sed 's/,[^,]*$//' "$tmp/g.csv" > "$tmp/g.cut"
sed 's/,[^,]*$//' "$tmp/e.csv" > "$tmp/e.cut"
cmp -s "$tmp/g.cut" "$tmp/e.cut" && ok || bad "decided with the group, every column but model_by as decided alone"
grep -q ',thin,' "$tmp/g.csv" && grep -q ',exact,' "$tmp/g.csv" && ok \
    || bad "the 5 x 5 map's batch mixes thin and exact fits"
for i in 1 2; do
    run_ok fit --batch "$tmp/fg/plan.csv" --threads 1 --shard $i/2 --out "$tmp/gs$i.csv"
done
{ cat "$tmp/gs1.csv"; tail -n +2 "$tmp/gs2.csv"; } | cmp -s - "$tmp/g.csv" && ok \
    || bad "with groups, shards 1..2 merged (one thread) differ from the whole (two)"
run_ok fit --batch "$tmp/fg/plan.csv" --threads 2 --out "$tmp/g.jsonl"
grep -q '"model_by": "group"' "$tmp/g.jsonl" && ok || bad "JSON Lines rows say model_by group"
expect_fail 2 "layerfit: fit: --model-each applies to --model auto only" \
    fit --batch "$tmp/fg/plan.csv" --model exact --model-each

# a bad curve gets a row and counts in the exit status; the rest go on
cp "$tmp/fm/plan.csv" "$tmp/fm/plan_bad.csv"
printf 'depth_nm,force_mN\n1,2\nthree,4\n' > "$tmp/fm/curves/bad.csv"
printf 'depth_nm,force_mN\n1,0\n2,0\n3,0\n4,0\n5,0\n6,0\n' > "$tmp/fm/curves/flat.csv"
printf 'curves/bad.csv,3,1mm,1um,frictionless\ncurves/flat.csv,3,1mm,1um,frictionless\n' >> "$tmp/fm/plan_bad.csv"
"$LF" fit --batch "$tmp/fm/plan_bad.csv" --out "$tmp/bad.csv" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 3 ] && ok || bad "two failed fits: exit 3 (some fits failed), got $rc"
has "stderr counts the failures" "$tmp/err" "layerfit: fit: 2 of 66 fits failed"
[ "$(wc -l < "$tmp/bad.csv")" -eq 67 ] && ok || bad "a row for every fit, bad ones too"
has "error row names file and line" "$tmp/bad.csv" "bad.csv:3:1:"
grep "flat.csv" "$tmp/bad.csv" | grep -q ",error," && ok || bad "flat curve: status error"
nok=$(awk -F, -v c="$cs" 'NR > 1 && $c == "ok"' "$tmp/bad.csv" | wc -l)
[ "$nok" -ge 62 ] && ok || bad "the good fits still ran"

# groups: curves of one sample are one joint fit
{ echo "file,k,R,b,interface,sample"
  echo "curves/x00_y00.csv,3,1mm,1um,frictionless,A"
  echo "curves/x01_y00.csv,3,1mm,1um,frictionless,"
  echo "curves/x00_y01.csv,3,1mm,1um,frictionless,A"
  echo "curves/x02_y00.csv,3,1mm,1um,frictionless,B"; } > "$tmp/fm/plan_groups.csv"
run_ok fit --batch "$tmp/fm/plan_groups.csv" --out "$tmp/g.csv"
[ "$(wc -l < "$tmp/g.csv")" -eq 4 ] && ok || bad "3 fits: A (2 curves), one alone, B"
has "group A first, both files" "$tmp/g.csv" "1,A,$tmp/fm/curves/x00_y00.csv;$tmp/fm/curves/x00_y01.csv,2,ok"
has "lone curve second" "$tmp/g.csv" "2,,$tmp/fm/curves/x01_y00.csv,1,ok"

# progress on request (otherwise only on a terminal)
run_ok fit --batch "$tmp/fm/plan.csv" --shard 1/8 --progress --out "$tmp/p.csv"
has "progress bar" "$tmp/err" "8/8 fits, 0 failed"

# the map of the result
if command -v gnuplot >/dev/null 2>&1; then
    run_ok map "$tmp/r1.csv" --plot "$tmp/map.png"
    [ "$(head -c 4 "$tmp/map.png" | od -An -c | tr -d ' ')" = "211PNG" ] && ok || bad "map.png is a PNG"
    [ -s "$tmp/map.gp" ] && [ -s "$tmp/map.dat" ] && ok || bad "map.gp and map.dat kept"
    [ "$(grep -c '^[0-9]' "$tmp/map.dat")" -eq 64 ] && ok || bad "map.dat has 64 pixels"
    (cd "$tmp" && gnuplot map.gp) && ok || bad "the kept script redraws the map"
    # a pixel without a fit is blank: '-' in map.dat (no NaN), the grid kept
    cp -r "$tmp/fm" "$tmp/fm3" && rm "$tmp/fm3/curves/x03_y05.csv"
    "$LF" fit --batch "$tmp/fm3/plan.csv" --model thin --intervals linear --out "$tmp/fm3/r.csv" 2>/dev/null
    mkdir -p "$tmp/m3" && run_ok map "$tmp/fm3/r.csv" --plot "$tmp/m3/map.png"
    [ "$(grep -c '^[0-9]' "$tmp/m3/map.dat")" -eq 64 ] && ok || bad "map with a hole: 64 pixels"
    [ "$(grep -c ' - -$' "$tmp/m3/map.dat")" -eq 1 ] && ok || bad "map with a hole: one blank pixel"
    grep -qi nan "$tmp/m3/map.dat" && bad "map with a hole: NaN in map.dat" || ok
    (cd "$tmp/m3" && gnuplot map.gp 2>"$tmp/gperr") && [ ! -s "$tmp/gperr" ] && ok \
        || bad "map with a hole: gnuplot: $(cat "$tmp/gperr")"
    # a one-row map (a QI line, 4 x 1): gnuplot's `with image` sizes its
    # pixels from two cells along each axis and draws nothing for one row,
    # so its cells are boxes; a panel with no value says so in words (no
    # colour range around nothing); a single value gets a colour range of
    # its own (no "empty cb range" warning reaching the user)
    mkdir -p "$tmp/m4" && printf 'x_m,y_m,w_J_m2,Estar_Pa,status\n' > "$tmp/m4/r.csv"
    for i in 0 1 2 3; do echo "$i.0e-6,-7e-6,,$((3 + i))000,ok"; done >> "$tmp/m4/r.csv"
    run_ok map "$tmp/m4/r.csv" --plot "$tmp/m4/row.svg"
    [ "$(grep -c '^-\?[0-9]' "$tmp/m4/row.dat")" -eq 4 ] && ok || bad "one-row map: 4 pixels"
    grep -q 'with image' "$tmp/m4/row.gp" && bad "one-row map drawn 'with image' (nothing drawn)" || ok
    has "one-row map: E* cells drawn as boxes" "$tmp/m4/row.gp" "\$4) with boxxyerror fs solid 1.0 noborder fc palette"
    has "one-row map: E* colour range of its values" "$tmp/m4/row.gp" "set cbrange [3:6]"
    has "w panel without a value says so" "$tmp/m4/row.svg" "w not determined at any point of the map"
    (cd "$tmp/m4" && gnuplot row.gp 2>"$tmp/gperr") && [ ! -s "$tmp/gperr" ] && ok \
        || bad "one-row map: gnuplot: $(cat "$tmp/gperr")"
    # (E*: values equal to the digits written are one value too)
    printf 'x_m,y_m,w_J_m2,Estar_Pa,status\n0,0,0.02,4000,ok\n1e-6,0,,4000.00001,ok\n0,1e-6,,4000,ok\n1e-6,1e-6,,4000,ok\n' \
        > "$tmp/m4/one.csv"
    "$LF" map "$tmp/m4/one.csv" --plot "$tmp/m4/one.png" >/dev/null 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 0 ] && [ ! -s "$tmp/err" ] && ok || bad "one w value: exit $rc, said '$(cat "$tmp/err")'"
    has "one w value: a colour range around it" "$tmp/m4/one.gp" "set cbrange [19:21]"
    has "one E* value to 6 digits: a colour range around it" "$tmp/m4/one.gp" "set cbrange [3.8:4.2]"
    grep -q 'with image' "$tmp/m4/one.gp" && ok || bad "a 2 x 2 map is an image"
else
    echo "note: gnuplot not installed, map drawing not tested"
fi
PATH=/nonexistent "$LF" map "$tmp/r1.csv" --plot "$tmp/map2.png" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 1 ] && ok || bad "map without gnuplot: exit 1, got $rc"
has "map without gnuplot says how to install it" "$tmp/err" "apt-get install gnuplot-nox"

# usage errors
expect_fail 2 "layerfit: fit: --out $tmp/r.txt: the batch output must end in .csv or .jsonl" \
    fit --batch "$tmp/fm/plan.csv" --out "$tmp/r.txt"
expect_fail 2 "layerfit: fit: --shard '0/3' is not I/N with 1 <= I <= N (e.g. --shard 3/8)" \
    fit --batch "$tmp/fm/plan.csv" --shard 0/3
expect_fail 2 "layerfit: fit: --shard '4/3' is not I/N with 1 <= I <= N (e.g. --shard 3/8)" \
    fit --batch "$tmp/fm/plan.csv" --shard 4/3
expect_fail 2 "layerfit: fit: --batch needs a plan or curve files (e.g. --batch plan.csv, --batch *.txt --k 2 --model halfspace)" fit --batch=
expect_fail 2 "layerfit: map: give one batch result (layerfit map RESULT.csv --plot map.png)" map
expect_fail 2 "layerfit: $tmp/fm/plan.csv:3: no column 'x_m': expected the CSV output of 'layerfit fit --batch PLAN --out RESULT.csv'" \
    map "$tmp/fm/plan.csv" --plot "$tmp/m.png"

# `fit --batch --help` is the batch's help, not a plan called --help
run_ok fit --batch --help
has "fit --batch --help" "$tmp/out" "usage: layerfit fit --batch PLAN.csv"
summary
