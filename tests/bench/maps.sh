#!/bin/sh
# maps.sh [LAYERFIT] [BENCH_READ] [CURVES]: reading files of many curves,
# reported, not asserted.
#  1. Speed: a synthetic QI map of CURVES curves (default 65 536, 256 x 256,
#     300 + 300 points, every entry deflated, as JPK writes them) is read
#     curve by curve (build/bench_read: open, then decode every curve) and
#     decompressed whole by `unzip -p FILE > /dev/null`; both in MB/s of
#     the file.
#  2. Memory: the peak RSS of `layerfit fit --batch MAP --k 2 ...` over QI
#     maps of 1024, 4096 and 16 384 curves (/usr/bin/time -v).
# The maps are written once into build/ by datasets/vendors/make_vendors.py.
LF=${1:-build/layerfit}
BR=${2:-build/bench_read}
curves=${3:-65536}
py=/usr/bin/python3
[ -x "$py" ] || py=python3

gen() {   # gen CURVES -> build/bench-qi-CURVES.jpk-qi-data
    f=build/bench-qi-$1.jpk-qi-data
    [ -f "$f" ] || { echo "generating $f" >&2; "$py" datasets/vendors/make_vendors.py --big "$1" "$f" || exit 1; }
    echo "$f"
}

big=$(gen "$curves")
cat "$big" > /dev/null      # the file in the page cache for both readers
echo "== reading $big"
if command -v unzip >/dev/null 2>&1; then
    t0=$(date +%s.%N); unzip -p "$big" > /dev/null; t1=$(date +%s.%N)
    awk -v t="$(echo "$t1 - $t0" | bc)" -v b="$(wc -c < "$big")" \
        'BEGIN { printf "unzip -p FILE > /dev/null: %.3f s, %.1f MB/s\n", t, b / 1e6 / t }'
else
    echo "unzip not installed: no comparison"
fi
"$BR" "$big" 1
"$BR" "$big" 2

echo "== peak memory of fit --batch over a map, by its number of curves"
for n in 1024 4096 16384; do
    f=$(gen "$n")
    out=$(mktemp); log=$(mktemp)
    /usr/bin/time -v "$LF" fit --batch "$f" --k 2 --R 8um --model halfspace --intervals linear \
        --threads 2 --quiet --out "$out.csv" 2>"$log"
    rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$log")
    wall=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$log")
    ok=$(grep -c ',ok,' "$out.csv")
    printf '%6d curves (%5.1f MB): peak RSS %6s kB, wall %s, %d rows ok\n' "$n" \
        "$(echo "$(wc -c < "$f") / 1000000" | bc -l)" "$rss" "$wall" "$ok"
    rm -f "$out" "$out.csv" "$log"
done
