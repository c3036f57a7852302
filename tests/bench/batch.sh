#!/bin/sh
# batch.sh [LAYERFIT] [CURVES_PER_SIDE] [POINTS]: throughput and peak memory
# of `layerfit fit --batch` on a synthetic force map (default 128 x 128 =
# 16 384 curves of 300 points), with 1 thread and with all cores, and on a
# 16 times smaller map to show that memory does not grow with the number of
# curves.  Reported, not asserted.  The map is generated once into
# build/bench-forcemap-SIDE-POINTS.  FIT_ARGS (e.g. "--model thin") are
# passed to every fit; the default model is auto, as for a single fit.
LF=${1:-build/layerfit}
side=${2:-128}
points=${3:-300}
dir=build/bench-forcemap-$side-$points
small=build/bench-forcemap-$((side / 4))-$points
cores=$(nproc 2>/dev/null || echo 1)

gen() {
    [ -f "$1/plan.csv" ] && return
    echo "generating $1 ($2 x $2 curves of $points points)"
    "$LF" map --synthetic "$1" --size "$2" --points "$points" 2>/dev/null || exit 1
}
gen "$dir" "$side"
gen "$small" $((side / 4))

run() {   # run LABEL PLAN THREADS
    out=$(mktemp); log=$(mktemp)
    if [ -x /usr/bin/time ]; then
        /usr/bin/time -v "$LF" fit --batch "$2" --threads "$3" --quiet --out "$out.csv" $FIT_ARGS 2>"$log"
        wall=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$log")
        rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$log")
    else
        t0=$(date +%s.%N)
        "$LF" fit --batch "$2" --threads "$3" --quiet --out "$out.csv" $FIT_ARGS 2>"$log"
        wall=$(echo "$(date +%s.%N) - $t0" | bc); rss="?"
    fi
    n=$(($(wc -l < "$out.csv") - 1))
    failed=$(awk -F, 'NR > 1 && $5 != "ok"' "$out.csv" | wc -l)
    printf '%-34s %6d fits  %2d thread(s)  wall %-9s  peak RSS %s kB  (%d not ok)\n' \
        "$1" "$n" "$3" "$wall" "$rss" "$failed"
    rm -f "$out" "$out.csv" "$log"
}
echo "machine: $cores core(s); layerfit $("$LF" --version); fit options: ${FIT_ARGS:-(defaults)}"
run "map $((side / 4))x$((side / 4)), $points points" "$small/plan.csv" "$cores"
run "map ${side}x$side, $points points" "$dir/plan.csv" 1
run "map ${side}x$side, $points points" "$dir/plan.csv" "$cores"
