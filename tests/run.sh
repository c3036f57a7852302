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
# the Python package (tests/python) on this build's library; a sanitizer
# build's library is loaded with its runtime first (LD_PRELOAD), leaks not
# counted (the interpreter keeps its own objects to the end)
if [ -d "$top/tests/python" ]; then
    pre=""
    if nm "$build/liblayerfit.a" 2>/dev/null | grep -q __asan_; then
        pre="$(${CC:-cc} -print-file-name=libasan.so) $(${CC:-cc} -print-file-name=libubsan.so)"
    fi
    run_one "python" env PYTHONPATH="$top/src/python" PYTHONDONTWRITEBYTECODE=1 \
        LAYERFIT_LIBRARY="$top/$build/$(cd "$build" && ls liblayerfit.so.[0-9]* | head -n 1)" \
        LAYERFIT_BUILD="$top/$build" LD_PRELOAD="$pre" \
        ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
        /usr/bin/python3 -m pytest -q -rs -p no:cacheprovider "$top/tests/python"
fi
[ -n "$broken" ] && echo "broken:$broken"
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
