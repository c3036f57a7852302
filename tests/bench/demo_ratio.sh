#!/bin/sh
# demo_ratio.sh [LAYERFIT] [RUNS]: the whole-process cost of the default
# `--model auto` against `--model thin` on datasets/demo/plan.csv (issue
# 13's "auto within 3x thin once the cache is warm").  The two runs
# alternate RUNS times (default 21) so that both see the same moments of a
# noisy machine; the medians and their ratio are printed.  Then one cold
# `auto` run, with an empty table cache of its own.  Reported, not asserted.
LF=${1:-build/layerfit}
runs=${2:-21}
plan=datasets/demo/plan.csv
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT

ms() {   # ms CMD...: wall time of CMD in milliseconds (output discarded)
    t0=$(date +%s%N)
    "$@" >/dev/null 2>&1
    t1=$(date +%s%N)
    echo $(( (t1 - t0) / 1000 ))
}

"$LF" fit "$plan" >/dev/null 2>&1 || { echo "demo_ratio: $LF fit $plan failed" >&2; exit 1; }
i=0
while [ "$i" -lt "$runs" ]; do
    ms "$LF" fit "$plan" >>"$tmp/auto"
    ms "$LF" fit --model thin "$plan" >>"$tmp/thin"
    i=$((i + 1))
done
med() { sort -n "$1" | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
a=$(med "$tmp/auto")
t=$(med "$tmp/thin")
cold=$(XDG_CACHE_HOME="$tmp/cache" ms "$LF" fit "$plan")
awk -v a="$a" -v t="$t" -v c="$cold" -v n="$runs" 'BEGIN {
    printf "auto (warm cache) median %.1f ms, thin median %.1f ms over %d alternated runs: %.2fx\n",
           a / 1000, t / 1000, n, a / t
    printf "auto, cold (empty cache, tables built): %.0f ms\n", c / 1000
}'
