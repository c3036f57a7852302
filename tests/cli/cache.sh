# cache.sh: `layerfit cache list|clear|dir`, --no-cache and
# LAYERFIT_NO_CACHE, the same fit from a cold and a warm cache, a damaged
# file rebuilt, and two processes filling the cache at once.  The cache is a
# folder of this test's own (XDG_CACHE_HOME), never the user's.
. "$(dirname "$0")/common"

XDG_CACHE_HOME="$tmp/xdg"; export XDG_CACHE_HOME
unset LAYERFIT_NO_CACHE
cdir="$tmp/xdg/layerfit"

run_ok cache dir
has "dir from XDG_CACHE_HOME" "$tmp/out" "$cdir"
run_ok cache list
has "empty list" "$tmp/out" "0 table files, 0 bytes, in $cdir"
run_ok cache --help
has "help names the folder" "$tmp/out" 'XDG_CACHE_HOME/layerfit'
expect_fail 2 "layerfit: cache: unknown action 'purge' (list, clear or dir)" cache purge
expect_fail 2 "layerfit: cache: give one of list, clear, dir (see 'layerfit cache --help')" cache

# a k = 2 curve on a 1 um layer: the auto choice needs the exact table
run_ok --no-cache simulate --out "$tmp/x" --model exact --w 10mJ/m2 --E 1GPa --noise 0.005 --seed 3 \
    --z0 15nm k=2,R=1mm,b=1um,interface=frictionless

# without the cache: nothing written, either way of asking
run_ok --no-cache fit "$tmp/x/plan.csv" && cp "$tmp/out" "$tmp/nocache.txt"
run_ok fit "$tmp/x/plan.csv" --no-cache && cp "$tmp/out" "$tmp/nocache2.txt"
LAYERFIT_NO_CACHE=1 run_ok fit "$tmp/x/plan.csv" && cp "$tmp/out" "$tmp/nocache3.txt"
if [ -d "$cdir" ] && [ -n "$(ls -A "$cdir")" ]; then bad "--no-cache wrote $(ls "$cdir")"; else ok; fi

# cold, then warm: the same report, and the table listed
run_ok fit "$tmp/x/plan.csv" && cp "$tmp/out" "$tmp/cold.txt"
run_ok fit "$tmp/x/plan.csv" && cp "$tmp/out" "$tmp/warm.txt"
for f in nocache2 nocache3 cold warm; do
    if cmp -s "$tmp/nocache.txt" "$tmp/$f.txt"; then ok; else bad "report $f differs from --no-cache"; fi
done
run_ok cache list
has "list names the table" "$tmp/out" "exact-k2-frictionless.lft"
has "list says what it is" "$tmp/out" "exact model, k = 2, frictionless base"
has "list total" "$tmp/out" "1 table file, "

# a damaged file is listed as such, rebuilt, and the report is unchanged
f="$cdir/exact-k2-frictionless.lft"
size=$(wc -c <"$f")
head -c $((size / 2)) "$f" >"$tmp/half" && cat "$tmp/half" >"$f"
run_ok cache list
has "damaged file listed" "$tmp/out" "truncated (rebuilt when next needed)"
run_ok fit "$tmp/x/plan.csv"
if cmp -s "$tmp/nocache.txt" "$tmp/out"; then ok; else bad "report after a damaged file differs"; fi
if [ "$(wc -c <"$f")" -eq "$size" ]; then ok; else bad "damaged file not rewritten whole"; fi
run_ok cache list
if grep -q "not usable" "$tmp/out"; then bad "rewritten file still not usable"; else ok; fi

# two processes filling an empty cache at once
run_ok cache clear
has "clear says how many" "$tmp/out" "removed 1 table file from $cdir"
"$LF" fit "$tmp/x/plan.csv" >"$tmp/p1.txt" 2>&1 &
p1=$!
"$LF" fit "$tmp/x/plan.csv" >"$tmp/p2.txt" 2>&1 &
p2=$!
wait $p1; r1=$?
wait $p2; r2=$?
if [ $r1 -eq 0 ] && [ $r2 -eq 0 ]; then ok; else bad "concurrent fits failed ($r1, $r2)"; fi
for p in p1 p2; do
    if cmp -s "$tmp/nocache.txt" "$tmp/$p.txt"; then ok; else bad "concurrent report $p differs"; fi
done
run_ok cache list
has "one whole file after the race" "$tmp/out" "1 table file, "
if grep -q "not usable" "$tmp/out"; then bad "file from the race not usable"; else ok; fi
if ls -A "$cdir" | grep -q '^\.'; then bad "temporary files left: $(ls -A "$cdir")"; else ok; fi

# HOME when XDG_CACHE_HOME is unset
HOME="$tmp/home" XDG_CACHE_HOME= run_ok cache dir
has "dir from HOME" "$tmp/out" "$tmp/home/.cache/layerfit"

summary
