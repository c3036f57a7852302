# safety.sh: what layerfit promises about its outputs (README, "What
# layerfit promises about its outputs"), tried as a hostile user would:
# names that try to run commands, outputs that would replace inputs, runs
# killed mid-write, FIFOs, full disks, names that are not UTF-8.
. "$(dirname "$0")/common"

PY=/usr/bin/python3
PROBE="--k 2 --R 1mm --b 1um --interface frictionless"
have_gnuplot=0; command -v gnuplot >/dev/null 2>&1 && have_gnuplot=1
sha() { sha256sum "$1" | cut -d' ' -f1; }

run_ok simulate --out "$tmp/s" --w 12.3mJ/m2 --E 1.85GPa --noise 0.005 --seed 7 --z0 15nm \
    --past-c 2 --delta-max 20nm k=2,R=1mm,b=1um,interface=frictionless \
    k=3,R=1mm,b=1um,interface=frictionless
good="$tmp/s/curve1.csv"

# ---- data never becomes code ---------------------------------------------
mkdir -p "$tmp/h"
cd "$tmp/h" || exit 1
for name in 'x";system "touch pwned" #.csv' "x';system 'touch pwned' #.csv" \
            'x`touch pwned`$(touch pwned).csv'; do
    cp "$good" "$name"
    rm -rf fig rep.html pwned fig/pwned
    "$LF" fit "$name" $PROBE --plot fig >/dev/null 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 0 ] && ok || bad "hostile name, --plot: exit $rc: $(cat "$tmp/err")"
    "$LF" fit "$name" $PROBE --report rep.html >/dev/null 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 0 ] && ok || bad "hostile name, --report: exit $rc: $(cat "$tmp/err")"
    [ ! -e pwned ] && [ ! -e fig/pwned ] && ok || bad "a file name ran a command: $name"
    if [ "$have_gnuplot" -eq 1 ]; then
        [ -s fig/curve1.svg ] && [ -s fig/curve1.png ] && [ -s fig/overview.svg ] && ok \
            || bad "hostile name: figures not drawn: $(cat "$tmp/err")"
    fi
    grep -q '<script type="application/json" id="lf-data">{"kind":"fit"' rep.html && ok \
        || bad "hostile name: report without its data"
    rm -f "$name"
done
# quotes, a backslash and a line break: still figures, one line per comment
name=$(printf 'we"i\\rd\nna'"'"'me.csv')
cp "$good" "$name"
rm -rf fig
"$LF" fit "$name" $PROBE --plot fig --json n.json >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] && ok || bad "odd name: exit $rc: $(cat "$tmp/err")"
[ "$(grep -c '^# curve 1: ' fig/overview.dat)" -eq 1 ] && ok || bad "overview.dat: curve comment"
grep -q "^na'me.csv" fig/overview.dat fig/curve1.dat && bad "a line break in a name broke a .dat file" || ok
if [ "$have_gnuplot" -eq 1 ]; then
    [ -s fig/overview.svg ] && [ -s fig/curve1.svg ] && ok || bad "odd name: no figures"
fi
$PY -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["curves"][0]["file"]==sys.argv[2]' \
    n.json "$name" 2>"$tmp/err" && ok || bad "odd name does not read back from JSON: $(cat "$tmp/err")"
rm -f "$name"
cd "$top" || exit 1

# ---- nothing lost: an output never replaces an input ----------------------
cp "$tmp/s/plan.csv" "$tmp/s/plan.orig"
cp "$good" "$tmp/c1.orig"
"$LF" fit --batch "$tmp/s/plan.csv" --out "$tmp/s/plan.csv" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "--out PLAN: exit $rc, want 2"
has "--out PLAN refused" "$tmp/err" "is the input"
cmp -s "$tmp/s/plan.csv" "$tmp/s/plan.orig" && ok || bad "--out PLAN changed the plan"
ln -s plan.csv "$tmp/s/link.csv"
"$LF" fit --batch "$tmp/s/plan.csv" --out "$tmp/s/link.csv" >/dev/null 2>&1; rc=$?
[ "$rc" -eq 2 ] && ok || bad "--out SYMLINK-TO-PLAN: exit $rc, want 2"
"$LF" fit --batch "$tmp/s/plan.csv" --out "$tmp/s/./curve1.csv" >/dev/null 2>&1; rc=$?
[ "$rc" -eq 2 ] && ok || bad "--out CURVE (./ path): exit $rc, want 2"
"$LF" fit "$tmp/s/plan.csv" --json "$tmp/s/curve2.csv" >/dev/null 2>&1; rc=$?
[ "$rc" -eq 2 ] && ok || bad "fit PLAN --json CURVE: exit $rc, want 2"
"$LF" fit "$good" $PROBE --curves "$good" >/dev/null 2>&1; rc=$?
[ "$rc" -eq 2 ] && ok || bad "fit CURVE --curves CURVE: exit $rc, want 2"
cmp -s "$good" "$tmp/c1.orig" && ok || bad "an output replaced a curve"
cmp -s "$tmp/s/plan.csv" "$tmp/s/plan.orig" && ok || bad "an output replaced the plan"
# two outputs of one run in one file: refused before anything is written
# (one would replace the other), under any spelling, sidecars and --plot's
# files included
mkdir -p "$tmp/two"
echo keep > "$tmp/two/old.json"
expect_fail 2 "layerfit: fit: $tmp/two/old.json is named for two outputs: one would replace the other (name them apart)" \
    fit "$tmp/s/plan.csv" --json "$tmp/two/old.json" --curves "$tmp/two/old.json"
[ "$(cat "$tmp/two/old.json")" = keep ] && ok || bad "two outputs: the earlier file changed"
expect_fail 2 "layerfit: fit: outputs $tmp/two/./c.csv.provenance.json and $tmp/two/c.csv.provenance.json are the same file: one would replace the other (name them apart)" \
    fit "$tmp/s/plan.csv" --curves "$tmp/two/c.csv" --json "$tmp/two/./c.csv.provenance.json"
mkdir -p "$tmp/two/p"
expect_fail 2 "layerfit: fit: $tmp/two/p/provenance.json is named for two outputs: one would replace the other (name them apart)" \
    fit "$tmp/s/plan.csv" --json "$tmp/two/p/provenance.json" --plot "$tmp/two/p"
expect_fail 2 "layerfit: fit: two outputs to standard output ('-'): name a file for all but one" \
    fit "$tmp/s/plan.csv" --json - --curves -
[ -e "$tmp/two/c.csv" ] || [ -e "$tmp/two/p/provenance.json" ] && bad "two outputs: something was written" || ok
# a batch's provenance sidecar (OUT.provenance.json) never replaces its plan
cp "$tmp/s/plan.csv" "$tmp/s/r.csv.provenance.json"
expect_fail 2 "layerfit: fit: output $tmp/s/r.csv.provenance.json is the input $tmp/s/r.csv.provenance.json: refusing to replace an input (name another output)" \
    fit --batch "$tmp/s/r.csv.provenance.json" --out "$tmp/s/r.csv"
cmp -s "$tmp/s/r.csv.provenance.json" "$tmp/s/plan.csv" && ok || bad "batch sidecar replaced its plan"
# an output through a symbolic link replaces the link's target, not the link;
# a pipe, a device or "-" is written in place, never replaced by a file
mkdir -p "$tmp/ln"
echo old >"$tmp/ln/target.json"
ln -s target.json "$tmp/ln/link.json"
run_ok fit "$good" $PROBE --json "$tmp/ln/link.json"
[ -L "$tmp/ln/link.json" ] && ok || bad "--json LINK: the link was replaced by a file"
has "--json LINK: the target holds the JSON" "$tmp/ln/target.json" '"parameters"'
ln -s nothere.json "$tmp/ln/dangling.json"
"$LF" fit "$good" $PROBE --json "$tmp/ln/dangling.json" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 1 ] && ok || bad "--json DANGLING-LINK: exit $rc, want 1"
has "--json DANGLING-LINK: said" "$tmp/err" "a symbolic link to a file that does not exist"
[ -L "$tmp/ln/dangling.json" ] && [ ! -e "$tmp/ln/nothere.json" ] && ok \
    || bad "--json DANGLING-LINK: something was written"
run_ok fit "$good" $PROBE --json -
has "--json -: the JSON on standard output" "$tmp/out" '"parameters"'
[ ! -e ./- ] && ok || { bad "--json - wrote a file named '-'"; rm -f ./-; }
if mkfifo "$tmp/ln/pipe.json" 2>/dev/null; then
    # (a reader that would wait for ever on a pipe replaced by a file is
    # stopped; /dev/null and /dev/stdout are not tried: a regression would
    # replace them for the whole machine)
    timeout 60 cat "$tmp/ln/pipe.json" >"$tmp/ln/got.json" &
    reader=$!
    run_ok fit "$good" $PROBE --json "$tmp/ln/pipe.json"
    [ -p "$tmp/ln/pipe.json" ] || kill "$reader" 2>/dev/null
    wait "$reader"
    [ -p "$tmp/ln/pipe.json" ] && ok || bad "--json FIFO: the pipe was replaced by a file"
    has "--json FIFO: the reader got the JSON" "$tmp/ln/got.json" '"parameters"'
fi

# an output in a folder that does not exist: exit 1 before the fit runs
"$LF" fit "$good" $PROBE --json "$tmp/nodir/x.json" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 1 ] && ok || bad "--json NODIR/x.json: exit $rc, want 1"
has "--json NODIR/x.json: said" "$tmp/err" "cannot write $tmp/nodir/x.json: there is no folder $tmp/nodir"
[ ! -s "$tmp/out" ] && ok || bad "--json NODIR/x.json: the fit ran and printed first"
"$LF" fit "$good" $PROBE --plot "$tmp/nodir/sub" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 1 ] && ok || bad "--plot NODIR/sub: exit $rc, want 1"
run_ok fit "$good" $PROBE --plot "$tmp/newfigs/"
echo keep > "$tmp/afile"
"$LF" fit "$good" $PROBE --plot "$tmp/afile" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 1 ] && [ ! -s "$tmp/out" ] && ok || bad "--plot FILE: exit $rc (want 1) or the fit ran first"
has "--plot FILE: said" "$tmp/err" "--plot $tmp/afile: that is a file, not a folder"
[ -s "$tmp/newfigs/curve1.gp" ] && ok || bad "--plot NEWDIR/ (a trailing slash): not made"

# --plot DIR: an input named like one of its files (an image gnuplot draws,
# a script, its data, the provenance) is refused before anything is written
mkdir -p "$tmp/pl"
for nm in curve1.svg curve1.png overview.dat curve1.gp provenance.json; do
    rm -rf "$tmp/pl"/* "$tmp/pl"/.layerfit-*
    cp "$good" "$tmp/pl/$nm"
    "$LF" fit "$tmp/pl/$nm" $PROBE --plot "$tmp/pl" >/dev/null 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 2 ] && ok || bad "--plot DIR over the input $nm: exit $rc, want 2"
    has "--plot DIR over the input $nm refused" "$tmp/err" "refusing to replace an input"
    cmp -s "$tmp/pl/$nm" "$good" && ok || bad "--plot DIR replaced the input $nm"
    [ "$(ls -A "$tmp/pl")" = "$nm" ] && ok || bad "--plot DIR over $nm left files: $(ls -A "$tmp/pl")"
done
# ... also a curve of a plan
rm -rf "$tmp/pl"/*
cp "$good" "$tmp/pl/overview.svg"
printf 'file,k,R_mm,b_um,interface\noverview.svg,2,1,1,frictionless\n' > "$tmp/pl/plan.csv"
"$LF" fit "$tmp/pl/plan.csv" --plot "$tmp/pl" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "--plot DIR over a plan's curve: exit $rc, want 2: $(cat "$tmp/err")"
cmp -s "$tmp/pl/overview.svg" "$good" && ok || bad "--plot DIR replaced a plan's curve"

# simulate and map --synthetic keep an earlier run unless --force
cp "$tmp/s/truth.csv" "$tmp/truth.orig"
"$LF" simulate --out "$tmp/s" --w 1mJ/m2 --E 1GPa k=2,R=1mm,b=1um >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "simulate over an earlier run: exit $rc, want 2"
has "simulate says why" "$tmp/err" "exists: not replaced without --force"
cmp -s "$tmp/s/truth.csv" "$tmp/truth.orig" && cmp -s "$good" "$tmp/c1.orig" && ok \
    || bad "simulate replaced files without --force"
run_ok simulate --out "$tmp/s2" --w 1mJ/m2 --E 1GPa k=2,R=1mm,b=1um
run_ok simulate --out "$tmp/s2" --w 2mJ/m2 --E 1GPa k=2,R=1mm,b=1um --force
has "--force replaces" "$tmp/s2/truth.csv" "0.002"
run_ok map --synthetic "$tmp/m" --size 2 --points 40
"$LF" map --synthetic "$tmp/m" --size 2 --points 40 >/dev/null 2>&1; rc=$?
[ "$rc" -eq 2 ] && ok || bad "map --synthetic over an earlier map: exit $rc, want 2"
run_ok map --synthetic "$tmp/m" --size 2 --points 40 --force

# a batch killed with SIGKILL mid-write leaves the earlier results as they were
run_ok map --synthetic "$tmp/big" --size 60 --points 300
"$LF" fit --batch "$tmp/m/plan.csv" --out "$tmp/big/results.csv" >/dev/null 2>&1
cp "$tmp/big/results.csv" "$tmp/results.orig"
"$LF" fit --batch "$tmp/big/plan.csv" --threads 1 --quiet --out "$tmp/big/results.csv" \
    >/dev/null 2>&1 &
pid=$!
i=0
while [ $i -lt 200 ]; do     # until the new results are being written
    t=$(ls "$tmp/big"/.results.csv.* 2>/dev/null | head -n 1)
    [ -n "$t" ] && [ -s "$t" ] && break
    i=$((i + 1)); sleep 0.05
done
if kill -0 $pid 2>/dev/null; then
    kill -9 $pid; wait $pid 2>/dev/null
    cmp -s "$tmp/big/results.csv" "$tmp/results.orig" && ok \
        || bad "a batch killed mid-write damaged the earlier results.csv"
    ok
else
    wait $pid; bad "the batch finished before it could be killed (make it bigger)"
fi

# ---- write errors are errors ------------------------------------------------
if [ -w /dev/full ]; then
    "$LF" fit "$good" $PROBE >/dev/full 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 1 ] && ok || bad "fit > /dev/full: exit $rc, want 1"
    has "/dev/full: message" "$tmp/err" "error writing standard output"
    "$LF" check "$good" >/dev/full 2>/dev/null; rc=$?
    [ "$rc" -eq 1 ] && ok || bad "check > /dev/full: exit $rc, want 1"
    "$LF" fit --batch "$tmp/s/plan.csv" >/dev/full 2>/dev/null; rc=$?
    [ "$rc" -eq 1 ] && ok || bad "fit --batch > /dev/full: exit $rc, want 1"
    "$LF" model --help >/dev/full 2>/dev/null; rc=$?
    [ "$rc" -eq 1 ] && ok || bad "model --help > /dev/full: exit $rc, want 1"
else
    echo "skipped: /dev/full not writable"
fi

# ---- inputs that must not hang or mislead -----------------------------------
mkfifo "$tmp/fifo"
cat "$good" > "$tmp/fifo" &
timeout 30 "$LF" check "$tmp/fifo" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] && ok || bad "check FIFO: exit $rc: $(cat "$tmp/err")"
"$LF" check "$good" >"$tmp/want" 2>/dev/null
sed 1d "$tmp/out" >"$tmp/got"; sed 1d "$tmp/want" >"$tmp/want1"
cmp -s "$tmp/got" "$tmp/want1" && ok || bad "check FIFO reads what check FILE reads"
wait
cat "$good" | timeout 30 "$LF" check /dev/stdin >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] && ok || bad "check /dev/stdin (a pipe): exit $rc: $(cat "$tmp/err")"
has "a pipe is read once, whole" "$tmp/out" "points"
if command -v bash >/dev/null 2>&1; then     # process substitution
    timeout 30 bash -c '"$0" check <(cat "$1")' "$LF" "$good" >"$tmp/out" 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 0 ] && ok || bad "check <(cat FILE): exit $rc: $(cat "$tmp/err")"
    sed 1d "$tmp/out" >"$tmp/got"
    cmp -s "$tmp/got" "$tmp/want1" && ok || bad "check <(cat FILE) reads what check FILE reads"
fi
cat "$good" | timeout 30 "$LF" fit /dev/stdin $PROBE >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] && ok || bad "fit /dev/stdin: exit $rc: $(cat "$tmp/err")"
# nobody writes: an error after a bounded wait, not a hang
timeout 60 "$LF" check "$tmp/fifo" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "check FIFO without a writer: exit $rc, want 2"
has "FIFO without a writer: message" "$tmp/err" "a FIFO needs a writer"
# a FIFO in a plan is refused at once, as that curve's row
cp "$tmp/s/plan.csv" "$tmp/s/plan_fifo.csv"
mkfifo "$tmp/s/curve9.csv"
echo "curve9.csv,2,0.001,1e-06,frictionless," >> "$tmp/s/plan_fifo.csv"
timeout 30 "$LF" fit --batch "$tmp/s/plan_fifo.csv" --out "$tmp/fifo.csv" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 3 ] && ok || bad "batch with a FIFO curve: exit $rc, want 3"
grep "curve9.csv" "$tmp/fifo.csv" | grep -q ",error,.*is not a regular file" && ok \
    || bad "FIFO curve: error row"
[ "$(grep -c ',ok,' "$tmp/fifo.csv")" -eq 2 ] && ok || bad "FIFO curve: the other fits go on"
timeout 30 "$LF" fit "$tmp/s/plan_fifo.csv" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "joint fit with a FIFO curve: exit $rc, want 2"
has "joint fit: FIFO refused" "$tmp/err" "is not a regular file"

# --threads is bounded
for t in 0 1025 99999999999999999999; do
    "$LF" fit --batch "$tmp/s/plan.csv" --threads $t >/dev/null 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 2 ] && ok || bad "--threads $t: exit $rc, want 2"
done
has "--threads: message" "$tmp/err" "--threads"

# a long plan cell is read whole: '1' + spaces + 'mm' is 1 mm
sp=$(printf '%200s' '')
printf 'file,k,R,b,interface\ncurve1.csv,2,1%smm,1um,frictionless\n' "$sp" > "$tmp/s/plan_long.csv"
run_ok check "$tmp/s/plan_long.csv"
has "long cell: R = 1 mm" "$tmp/out" "R = 1 mm"

# a curve check refuses, fit refuses too (same check)
head -n 6 "$good" > "$tmp/five.csv"
"$LF" check "$tmp/five.csv" >/dev/null 2>"$tmp/e1"; r1=$?
"$LF" fit "$tmp/five.csv" $PROBE >/dev/null 2>"$tmp/e2"; r2=$?
[ "$r1" -eq 2 ] && [ "$r2" -eq 2 ] && ok || bad "5 points: check exit $r1, fit exit $r2, want 2 and 2"
cmp -s "$tmp/e1" "$tmp/e2" && ok || bad "5 points: check and fit say different things"

# ---- batches: every problem is that curve's row -----------------------------
cp "$tmp/s/plan.csv" "$tmp/s/plan_missing.csv"
echo "gone.csv,2,0.001,1e-06,frictionless," >> "$tmp/s/plan_missing.csv"
"$LF" fit --batch "$tmp/s/plan_missing.csv" --out "$tmp/miss.csv" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 3 ] && ok || bad "batch with a missing curve: exit $rc, want 3"
has "summary line" "$tmp/err" "layerfit: fit: 1 of 3 fits failed"
grep "gone.csv" "$tmp/miss.csv" | grep -q ",error," && ok || bad "missing curve: error row"
[ "$(grep -c ',ok,' "$tmp/miss.csv")" -eq 2 ] && ok || bad "missing curve: the batch goes on"

# ---- formats ------------------------------------------------------------------
# names that are not UTF-8: JSON and JSON Lines still parse, raw bytes kept
bad_name=$(printf 'bad\377\376name.csv')
cp "$good" "$tmp/s/$bad_name"
"$LF" fit "$tmp/s/$bad_name" $PROBE --json "$tmp/u.json" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] && ok || bad "fit of a non-UTF-8 name: exit $rc"
$PY -c 'import json,sys,urllib.parse as u
d = json.load(open(sys.argv[1], encoding="utf-8"))
c = d["curves"][0]
assert "\ufffd" in c["file"], c["file"]
assert u.unquote_to_bytes(c["file_raw"]) == sys.argv[2].encode("utf-8", "surrogateescape")
' "$tmp/u.json" "$tmp/s/$bad_name" 2>"$tmp/err" && ok || bad "JSON of a non-UTF-8 name: $(cat "$tmp/err")"
{ cat "$tmp/s/plan.csv"; printf '%s,2,0.001,1e-06,frictionless,\n' "$bad_name"; } > "$tmp/s/plan_u.csv"
"$LF" fit --batch "$tmp/s/plan_u.csv" --out "$tmp/u.jsonl" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] && ok || bad "batch with a non-UTF-8 name: exit $rc: $(cat "$tmp/err")"
$PY -c 'import json,sys,urllib.parse as u
rows = [json.loads(l) for l in open(sys.argv[1], encoding="utf-8")]
assert len(rows) == 3
r = rows[2]
assert u.unquote_to_bytes(r["files_raw"][0]) == sys.argv[2].encode("utf-8", "surrogateescape")
assert len(r["sha256"][0]) == 64
' "$tmp/u.jsonl" "$tmp/s/$bad_name" 2>"$tmp/err" && ok || bad "JSONL of a non-UTF-8 name: $(cat "$tmp/err")"

# a joint fit's file cell: names with ';' and '"' can be told apart
cp "$good" "$tmp/s/a;b.csv"
cp "$tmp/s/curve2.csv" "$tmp/s/q\"uote.csv"
printf 'file,k,R,b,interface,sample\n"a;b.csv",2,1mm,1um,frictionless,S\n"q""uote.csv",3,1mm,1um,frictionless,S\n' \
    > "$tmp/s/plan_joint.csv"
run_ok fit --batch "$tmp/s/plan_joint.csv" --out "$tmp/joint.csv"
$PY -c 'import csv,sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 1
cell = rows[0]["file"]
names = next(csv.reader([cell], delimiter=";"))
assert [n.rsplit("/", 1)[-1] for n in names] == ["a;b.csv", "q\"uote.csv"], names
assert len(rows[0]["sha256"].split(";")) == 2
' "$tmp/joint.csv" 2>"$tmp/err" && ok || bad "joint file cell: $(cat "$tmp/err")"

# provenance: version, command line, SHA-256 of every input
run_ok fit "$tmp/s/plan.csv" --json "$tmp/p.json" --curves "$tmp/p.csv" --report "$tmp/p.html" --plot "$tmp/pf"
$PY -c 'import json,sys
d = json.load(open(sys.argv[1]))["provenance"]
assert d["layerfit"] and "--json" in d["command_line"]
h = {i["file"].rsplit("/", 1)[-1]: i["sha256"] for i in d["inputs"]}
assert h["plan.csv"] == sys.argv[2] and h["curve1.csv"] == sys.argv[3], h
' "$tmp/p.json" "$(sha "$tmp/s/plan.csv")" "$(sha "$good")" 2>"$tmp/err" && ok \
    || bad "JSON provenance: $(cat "$tmp/err")"
has "curves CSV sidecar" "$tmp/p.csv.provenance.json" "$(sha "$good")"
has "HTML provenance" "$tmp/p.html" "$(sha "$good")"
has "plot folder provenance" "$tmp/pf/provenance.json" "$(sha "$good")"
run_ok fit --batch "$tmp/s/plan.csv" --out "$tmp/b.csv"
has "batch CSV: sha256 column" "$tmp/b.csv" "$(sha "$good")"
has "batch CSV sidecar" "$tmp/b.csv.provenance.json" "$(sha "$tmp/s/plan.csv")"
$PY -c 'import csv,sys; r = list(csv.DictReader(open(sys.argv[1]))); assert len(r) == 2' "$tmp/b.csv" \
    && ok || bad "batch CSV still parses as CSV"
ls -a "$tmp/s" "$tmp" | grep -q '^\.[^.].*\.[A-Za-z0-9]\{6\}$' && bad "temporary files left behind" || ok


# ==== issue 33: nothing a name, a stream or a signal can do ================
# (each case below failed on the build before it)
have_chattr=0
echo x >"$tmp/attr"; chattr +i "$tmp/attr" 2>/dev/null && { chattr -i "$tmp/attr"; have_chattr=1; }
lines() { wc -l <"$1" | tr -d ' '; }

# ---- no shell anywhere ---------------------------------------------------
# no source hands a command string to a shell
if grep -nE '(^|[^a-z_.])(popen|system)\(' "$top"/src/*.c "$top"/src/cli/*.c "$top"/fit/*.c \
        >"$tmp/shell.txt"; then
    bad "a shell is called: $(cat "$tmp/shell.txt")"
else ok; fi
if $PY -c 'import scipy.optimize' >/dev/null 2>&1; then
    # a peer script whose name is a shell command runs as a script, and so
    # does the default one under a folder whose name holds a quote
    mkdir -p "$tmp/pw"
    printf 'print("peer here")\n' >"$tmp/pw/x';touch PWNED;'.py"
    (cd "$tmp/pw" && "$LF" bench --quick --seeds 2 --batch 8 --scene single-k2 \
        --scipy "x';touch PWNED;'.py" >out 2>err)
    [ ! -e "$tmp/pw/PWNED" ] && ok || bad "bench --scipy NAME ran a shell command"
    has "bench --scipy NAME: the script ran" "$tmp/pw/err" "peer here"
    q="$tmp/it's here"
    mkdir -p "$q/build" "$q/tests/bench"
    cp "$LF" "$q/build/layerfit"
    printf 'print("default peer here")\n' >"$q/tests/bench/peer_scipy.py"
    (cd "$tmp/pw" && "$q/build/layerfit" bench --quick --seeds 2 --batch 8 --scene single-k2 \
        >out 2>err)
    has "bench under a folder with a quote: the script ran" "$tmp/pw/err" "default peer here"
    rm -rf "$q"
else
    echo "skipped: $PY has no scipy (the bench peer)"
fi

# ---- an output and its sidecar: a pair, checked before the fit -----------
mkdir -p "$tmp/pair"
run_ok fit --batch "$tmp/s/plan.csv" --out "$tmp/pair/o.csv"
cp "$tmp/pair/o.csv" "$tmp/pair/o.orig"
cp "$tmp/pair/o.csv.provenance.json" "$tmp/pair/side.orig"
rm "$tmp/pair/o.csv.provenance.json"
head -n 2 "$tmp/s/plan.csv" >"$tmp/s/pa.csv"
{ head -n 1 "$tmp/s/plan.csv"; sed -n 3p "$tmp/s/plan.csv"; } >"$tmp/s/pb.csv"
pair_refused() {     # WHAT: the sidecar is unwritable: exit 1 before the fit
    "$LF" fit --batch "$tmp/s/pa.csv" --out "$tmp/pair/o.csv" >"$tmp/out" 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 1 ] && ok || bad "$1: exit $rc, want 1"
    has "$1: said" "$tmp/err" "cannot "
    cmp -s "$tmp/pair/o.csv" "$tmp/pair/o.orig" && ok || bad "$1: the CSV was replaced"
    [ ! -s "$tmp/out" ] && ok || bad "$1: the fit ran and wrote first"
}
ln -s nowhere.json "$tmp/pair/o.csv.provenance.json"
pair_refused "sidecar a link to nothing"
rm "$tmp/pair/o.csv.provenance.json"
mkdir "$tmp/pair/o.csv.provenance.json"
pair_refused "sidecar a folder"
rmdir "$tmp/pair/o.csv.provenance.json"
if [ "$have_chattr" -eq 1 ]; then
    cp "$tmp/pair/side.orig" "$tmp/pair/o.csv.provenance.json"
    chattr +i "$tmp/pair/o.csv.provenance.json"
    pair_refused "sidecar immutable"
    chattr -i "$tmp/pair/o.csv.provenance.json"
    cmp -s "$tmp/pair/o.csv.provenance.json" "$tmp/pair/side.orig" && ok \
        || bad "immutable sidecar: changed"
    rm "$tmp/pair/o.csv.provenance.json"
else
    echo "skipped: chattr +i not allowed here (immutable sidecar)"
fi
# made unwritable while the batch runs: the pair is left as it was
run_ok map --synthetic "$tmp/mid" --size 18 --points 300
cp "$tmp/big/results.csv" "$tmp/mid/r2.csv"
cp "$tmp/big/results.csv" "$tmp/r2.orig"
mid_batch() {        # WHAT CMD: run CMD once the batch has made its temporary
    "$LF" fit --batch "$tmp/mid/plan.csv" --threads 1 --quiet --out "$tmp/mid/r2.csv" \
        >/dev/null 2>"$tmp/err" &
    pid=$!
    i=0
    while [ $i -lt 400 ] && [ -z "$(ls -a "$tmp/mid" | grep '^\.r2\.csv\.')" ]; do
        i=$((i + 1)); sleep 0.01
    done
    eval "$2"
    wait $pid; rc=$?
    [ "$rc" -eq 1 ] && ok || bad "$1: exit $rc, want 1: $(cat "$tmp/err")"
    cmp -s "$tmp/mid/r2.csv" "$tmp/r2.orig" && ok || bad "$1: the CSV was replaced"
    [ -z "$(ls -a "$tmp/mid" | grep '^\.r2\.csv')" ] && ok || bad "$1: temporaries left"
}
mid_batch "sidecar a folder made mid-run" 'mkdir "$tmp/mid/r2.csv.provenance.json"'
rmdir "$tmp/mid/r2.csv.provenance.json"
if [ "$have_chattr" -eq 1 ]; then
    cp "$tmp/pair/side.orig" "$tmp/mid/r2.csv.provenance.json"
    mid_batch "sidecar made immutable mid-run" 'chattr +i "$tmp/mid/r2.csv.provenance.json"'
    chattr -i "$tmp/mid/r2.csv.provenance.json"
    cmp -s "$tmp/mid/r2.csv.provenance.json" "$tmp/pair/side.orig" && ok \
        || bad "sidecar made immutable mid-run: changed"
fi
# two batches writing one --out at once leave one whole pair
mixed=0; i=0
while [ $i -lt 40 ]; do
    rm -f "$tmp/pair/c.csv" "$tmp/pair/c.csv.provenance.json"
    "$LF" fit --batch "$tmp/s/pa.csv" --out "$tmp/pair/c.csv" >/dev/null 2>&1 & a=$!
    "$LF" fit --batch "$tmp/s/pb.csv" --out "$tmp/pair/c.csv" >/dev/null 2>&1 & b=$!
    wait $a; wait $b
    if grep -q curve1.csv "$tmp/pair/c.csv"; then w=pa.csv; else w=pb.csv; fi
    grep -q "$w" "$tmp/pair/c.csv.provenance.json" || mixed=$((mixed + 1))
    i=$((i + 1))
done
[ "$mixed" -eq 0 ] && ok || bad "concurrent batches: $mixed of 40 pairs mixed"
# fit --curves and its sidecar: the same
ln -s nowhere.json "$tmp/pair/cv.csv.provenance.json"
"$LF" fit "$good" $PROBE --curves "$tmp/pair/cv.csv" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 1 ] && [ ! -e "$tmp/pair/cv.csv" ] && [ ! -s "$tmp/out" ] && ok \
    || bad "--curves with a dangling sidecar: exit $rc, or written"

# ---- streams read with limits ----------------------------------------------
# binary data, an endless line, an endless stream: stopped as they arrive
timeout 30 "$LF" check /dev/zero >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "check /dev/zero: exit $rc, want 2"
has "check /dev/zero: said" "$tmp/err" "binary data"
(echo depth_nm,force_uN; tr '\000' a </dev/zero) | timeout 30 "$LF" check /dev/stdin \
    >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "an endless line: exit $rc, want 2"
has "an endless line: said" "$tmp/err" "line longer than 1 MiB"
(echo depth_nm,force_uN; yes 1,2) | timeout 30 "$LF" check /dev/stdin --max-input 1MiB \
    >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "an endless stream: exit $rc, want 2"
has "an endless stream: said" "$tmp/err" "more than the 1 MiB layerfit reads whole (--max-input"
# a regular file past the limit is refused from its size, before reading
truncate -s 300M "$tmp/sparse.csv" 2>/dev/null || dd if=/dev/null of="$tmp/sparse.csv" bs=1 seek=300M 2>/dev/null
"$LF" check "$tmp/sparse.csv" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "a 300 MiB file: exit $rc, want 2"
has "a 300 MiB file: said" "$tmp/err" "holds 300 MiB, more than the 256 MiB layerfit reads whole"
rm -f "$tmp/sparse.csv"
# ... and so is a plan or a table read in blocks into what is kept
"$LF" --max-input 1KiB map "$tmp/big/results.csv" --plot "$tmp/lim.svg" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "map of a table past --max-input: exit $rc, want 2"
has "map of a table past --max-input: said" "$tmp/err" "more than the 1 KiB layerfit reads whole"
run_ok check "$good" --max-input 2GiB
expect_fail 2 "layerfit: --max-input: 'lots' is not a size in bytes (e.g. --max-input 2GiB, 512MiB or 1e9)" \
    check "$good" --max-input lots

# ---- outputs and caches never block ----------------------------------------
# a FIFO output nobody reads: exit 1 after a bounded wait, before the fit
mkdir -p "$tmp/ff"
for o in f.json c.csv r.html out.csv; do mkfifo "$tmp/ff/$o"; done
timeout 60 "$LF" fit "$good" $PROBE --json "$tmp/ff/f.json" >"$tmp/ff/o1" 2>"$tmp/ff/e1" &
p1=$!
timeout 60 "$LF" fit "$good" $PROBE --curves "$tmp/ff/c.csv" >"$tmp/ff/o2" 2>"$tmp/ff/e2" &
p2=$!
timeout 60 "$LF" fit "$good" $PROBE --report "$tmp/ff/r.html" >"$tmp/ff/o3" 2>"$tmp/ff/e3" &
p3=$!
timeout 60 "$LF" fit --batch "$tmp/s/plan.csv" --out "$tmp/ff/out.csv" >"$tmp/ff/o4" 2>"$tmp/ff/e4" &
p4=$!
# a FIFO in the table cache folder: passed over, not waited on
mkdir -p "$tmp/fcache/layerfit"
mkfifo "$tmp/fcache/layerfit/exact-k2-frictionless.lft"
XDG_CACHE_HOME="$tmp/fcache" timeout 60 "$LF" fit "$good" $PROBE --model exact \
    >/dev/null 2>"$tmp/ff/e5"; rc=$?
[ "$rc" -eq 0 ] && ok || bad "a FIFO in the table cache: exit $rc: $(cat "$tmp/ff/e5")"
n=1
for p in $p1 $p2 $p3 $p4; do
    wait $p; rc=$?
    [ "$rc" -eq 1 ] && ok || bad "FIFO output without a reader ($n): exit $rc, want 1"
    grep -q "nothing opened it for reading" "$tmp/ff/e$n" && ok \
        || bad "FIFO output without a reader ($n): $(cat "$tmp/ff/e$n")"
    [ ! -s "$tmp/ff/o$n" ] && ok || bad "FIFO output without a reader ($n): the fit ran first"
    n=$((n + 1))
done

# ---- no NaN or inf in any output -------------------------------------------
nonfinite() { grep -qiE '(^|[^a-z])[-+]?(nan|inf)([^a-z]|$)' "$@"; }
M="--R 1mm --b 1um --w 10mJ/m2 --E 1GPa"
for k in 0.01 0.3 1000 1e6; do
    for m in thin exact halfspace; do
        "$LF" model --model $m --k $k $M >"$tmp/out" 2>"$tmp/err"; rc=$?
        nonfinite "$tmp/out" && bad "model --model $m --k $k: NaN or inf written" || ok
        [ "$rc" -eq 0 ] || [ "$rc" -eq 2 ] && ok || bad "model --model $m --k $k: exit $rc"
        [ "$rc" -eq 0 ] || [ ! -s "$tmp/out" ] && ok || bad "model --model $m --k $k: refused after writing"
        grep -q "give --from and --to" "$tmp/err" && bad "model --model $m --k $k: blames --from/--to" || ok
    done
done
"$LF" model --model thin --k 0.01 $M --summary >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "model --k 0.01 --summary: exit $rc, want 2"
has "--k 0.01: the region named" "$tmp/err" "model thin cannot be evaluated at k = 0.01"
"$LF" model --k 2 --R 1e300m --b 1um --w 10mJ/m2 --E 1GPa >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && [ ! -s "$tmp/out" ] && ok || bad "model --R 1e300m: exit $rc, want 2"
run_ok model --k 1000 $M --summary
has "a flat punch k = 1000: its pull-off radius" "$tmp/out" "a = 988.4 µm"
for args in "k=0.01,R=1mm,b=1um" "k=1000,R=1mm,b=1um --model exact"; do
    rm -rf "$tmp/sim"
    "$LF" simulate --out "$tmp/sim" --w 10mJ/m2 --E 1GPa $args >/dev/null 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 2 ] && ok || bad "simulate $args: exit $rc, want 2"
    [ ! -e "$tmp/sim/curve1.csv" ] && ok || bad "simulate $args: a curve written"
done
"$LF" fit "$good" --k 1000 --R 1mm --b 1um --interface frictionless --model exact \
    >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && [ ! -s "$tmp/out" ] && ok || bad "fit --model exact --k 1000: exit $rc, want 2"
# map: a result holding inf, nan or 1e308 is refused at its cell
run_ok fit --batch "$tmp/m/plan.csv" --out "$tmp/m/r.csv"
for v in inf nan 1e308; do
    awk -F, -v v=$v 'BEGIN { OFS = "," } NR == 1 { for (i = 1; i <= NF; i++) if ($i == "x_m") c = i }
                     NR == 3 { $c = v } { print }' "$tmp/m/r.csv" >"$tmp/m/bad.csv"
    rm -f "$tmp/m/bad_map.dat" "$tmp/m/bad_map.gp"
    "$LF" map "$tmp/m/bad.csv" --plot "$tmp/m/bad_map.svg" >/dev/null 2>"$tmp/err"; rc=$?
    [ "$rc" -eq 2 ] && ok || bad "map with x_m = $v: exit $rc, want 2"
    has "map with x_m = $v: its cell" "$tmp/err" "$tmp/m/bad.csv:3:"
    [ ! -e "$tmp/m/bad_map.dat" ] && ok || bad "map with x_m = $v: data written"
done

# ---- names kept byte for byte; stdout for the output alone ------------------
mkdir -p "$tmp/nm"
cp "$good" "$tmp/nm/c3.csv"
cp "$tmp/s/curve2.csv" "$tmp/nm/ c3.csv"
printf 'file,k,R,b,interface\n" c3.csv",3,1mm,1um,frictionless\n' >"$tmp/nm/plan.csv"
run_ok check "$tmp/nm/plan.csv"
has "a quoted plan cell keeps its leading space" "$tmp/out" "$tmp/nm/ c3.csv (plan line 2)"
cr=$(printf 'a\rb.csv')
cp "$good" "$tmp/nm/$cr"
printf 'file,k,R,b,interface\n"a\rb.csv",2,1mm,1um,frictionless\n' >"$tmp/nm/plan_cr.csv"
run_ok check "$tmp/nm/plan_cr.csv"
run_ok fit --batch "$tmp/nm/plan.csv" --out "$tmp/nm/r.csv"
$PY -c 'import csv,sys; r = list(csv.DictReader(open(sys.argv[1]))); assert r[0]["file"].endswith("/ c3.csv"), r[0]["file"]' \
    "$tmp/nm/r.csv" 2>"$tmp/err" && ok || bad "a name with a leading space in batch output: $(cat "$tmp/err")"
run_ok fit "$good" $PROBE --json -
$PY -c 'import json,sys; json.load(open(sys.argv[1]))' "$tmp/out" 2>"$tmp/err" && ok \
    || bad "--json -: standard output is not the JSON alone: $(head -c 300 "$tmp/err")"

# ---- exit codes and messages -------------------------------------------------
expect_fail 2 "layerfit: fit: an output needs a name (got an empty one)" fit "$good" $PROBE --json ""
"$LF" fit "$good" $PROBE --report "$tmp/rp.html" --plot "$tmp/rp.html" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && [ ! -s "$tmp/out" ] && ok || bad "--report X --plot X: exit $rc, want 2 before the fit"
"$LF" fit "$good" --k 2 --R 1mm --b 1e-400m --interface frictionless >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "--b 1e-400m: exit $rc"
has "--b 1e-400m: too small" "$tmp/err" "is too small for double precision"
"$LF" model --model exact --k 0.01 $M >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && ok || bad "model --model exact --k 0.01: exit $rc"
grep -q -- "--from and --to" "$tmp/err" && bad "model --model exact --k 0.01 blames --from and --to" || ok
# a model that cannot be evaluated at the fit's start: 3, not 1
"$LF" fit "$good" $PROBE --fix-F0 1e300N >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 3 ] && ok || bad "--fix-F0 1e300N: exit $rc, want 3: $(cat "$tmp/err")"
# output names up to NAME_MAX (255 bytes) work; longer ones are refused
long=$(printf '%0249d' 0).json       # 254 bytes
run_ok fit "$good" $PROBE --json "$tmp/$long"
[ -s "$tmp/$long" ] && ok || bad "a 254-byte output name: not written"
long=$(printf '%0251d' 0).json       # 256 bytes
expect_fail 2 "layerfit: fit: cannot write $tmp/$long: a file name has at most 255 bytes (this one 256)" \
    fit "$good" $PROBE --json "$tmp/$long"
# a line break in a name stays on the message's line
"$LF" check "$(printf '%s/no\nsuch.csv' "$tmp")" >/dev/null 2>"$tmp/err"
[ "$(lines "$tmp/err")" -eq 1 ] && ok || bad "a line break in a name split the message"
has "the line break escaped" "$tmp/err" 'no\nsuch.csv'
esc=$(printf 'e\033[2Jf.csv')
"$LF" check "$tmp/$esc" >/dev/null 2>"$tmp/err"
has "an escape character escaped" "$tmp/err" 'e\x1b[2Jf.csv'
# CSV cells a spreadsheet would run: a leading quote; --csv-raw keeps them
cp "$good" "$tmp/nm/=1+2.csv"
printf 'file,k,R,b,interface,sample\n=1+2.csv,2,1mm,1um,frictionless,"=HYPERLINK(""http://x"")"\n' \
    >"$tmp/nm/plan_f.csv"
(cd "$tmp/nm" && "$LF" fit --batch plan_f.csv --out f.csv >/dev/null 2>&1) && ok || bad "a formula name: exit $?"
$PY -c 'import csv,sys
r = list(csv.DictReader(open(sys.argv[1])))[0]
assert r["sample"] == "'"'"'=HYPERLINK(\"http://x\")", r["sample"]
assert r["file"] == "'"'"'=1+2.csv", r["file"]
assert r["P_po_N"].startswith("-"), r["P_po_N"]       # a negative number stays a number
' "$tmp/nm/f.csv" 2>"$tmp/err" && ok || bad "CSV formula cells: $(cat "$tmp/err")"
run_ok --csv-raw fit --batch "$tmp/nm/plan_f.csv" --out "$tmp/nm/fr.csv"
$PY -c 'import csv,sys
r = list(csv.DictReader(open(sys.argv[1])))[0]
assert r["sample"] == "=HYPERLINK(\"http://x\")", r["sample"]
' "$tmp/nm/fr.csv" 2>"$tmp/err" && ok || bad "--csv-raw: $(cat "$tmp/err")"
# catchable signals remove the temporaries, and the run ends by the signal
for sig in TERM HUP INT; do
    rm -f "$tmp/big"/.r3.csv.*
    env --default-signal=INT "$LF" fit --batch "$tmp/big/plan.csv" --threads 1 --quiet \
        --out "$tmp/big/r3.csv" >/dev/null 2>&1 &
    pid=$!
    i=0
    while [ $i -lt 200 ]; do
        t=$(ls "$tmp/big"/.r3.csv.* 2>/dev/null | head -n 1)
        [ -n "$t" ] && [ -s "$t" ] && break
        i=$((i + 1)); sleep 0.05
    done
    kill -$sig $pid
    wait $pid; rc=$?
    [ "$rc" -gt 128 ] && ok || bad "SIG$sig: exit $rc (the run did not end by the signal)"
    [ -z "$(ls -a "$tmp/big" | grep '^\.r3\.csv')" ] && ok || bad "SIG$sig: temporaries left"
done
# --plot writes through a symbolic link in its folder (the link stays)
if [ "$have_gnuplot" -eq 1 ]; then
    mkdir -p "$tmp/lp" "$tmp/lt"
    echo old >"$tmp/lt/keep.svg"
    ln -s ../lt/keep.svg "$tmp/lp/curve1.svg"
    run_ok fit "$good" $PROBE --plot "$tmp/lp"
    [ -L "$tmp/lp/curve1.svg" ] && ok || bad "--plot: a link in the folder was replaced"
    grep -q '<svg' "$tmp/lt/keep.svg" && ok || bad "--plot: the link's target was not written"
fi
# repeated warnings are summarised
run_ok map --synthetic "$tmp/wm" --size 10 --points 40
run_ok check "$tmp/wm/plan.csv"
[ "$(lines "$tmp/err")" -le 6 ] && ok || bad "100 warnings of one kind: $(lines "$tmp/err") lines"
has "warnings summarised" "$tmp/err" "... and 97 more like it"
# the README says what the readers take: plan cells up to the line limit
grep -q 'Plan cells of any length' "$top/README.md" && bad "README: plan cells of any length" || ok
ls -a "$tmp/s" "$tmp/pair" "$tmp/nm" "$tmp" | grep '^\.[^.].*\.[A-Za-z0-9]\{6\}$' >"$tmp/left.txt"
[ -s "$tmp/left.txt" ] && bad "temporary files left behind: $(cat "$tmp/left.txt")" || ok

summary
