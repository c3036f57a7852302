#!/bin/sh
# run.sh BUILD: run every test program in BUILD/tests and every CLI test
# script in tests/cli, then print the grand total as "N passed, N failed".
build=${1:-build}
top=$(cd "$(dirname "$0")/.." && pwd)
total_pass=0; total_fail=0; broken=""
log=$(mktemp); cache=$(mktemp -d); trap 'rm -f "$log"; rm -rf "$cache"' EXIT
# the exact model's tables go to a cache of the run's own, never the user's
XDG_CACHE_HOME=$cache; LAYERFIT_TEST_CACHE=1; export XDG_CACHE_HOME LAYERFIT_TEST_CACHE
run_one() {
    name=$1; shift
    "$@" >"$log" 2>&1; rc=$?
    line=$(grep -E '^[0-9]+ passed, [0-9]+ failed$' "$log" | tail -n 1)
    if [ -z "$line" ]; then
        cat "$log"; echo "$name: no summary (exit $rc)"; broken="$broken $name"
        total_fail=$((total_fail + 1)); return
    fi
    p=${line%% passed*}; f=${line#*passed, }; f=${f%% failed}
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; broken="$broken $name"; fi
    [ "$f" -ne 0 ] && grep -v '^PASS' "$log" | head -n 60
    printf '%-28s %s\n' "$name" "$line"
    total_pass=$((total_pass + p)); total_fail=$((total_fail + f))
}
for t in "$build"/tests/test_*; do
    [ -x "$t" ] || continue
    run_one "$(basename "$t")" "$t"
done
for s in "$top"/tests/cli/*.sh; do
    [ -f "$s" ] || continue
    run_one "cli/$(basename "$s" .sh)" sh "$s" "$top/$build/layerfit"
done
[ -n "$broken" ] && echo "broken:$broken"
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
