#!/bin/sh
# report.sh LAYERFIT: the map report of a synthetic 128 x 128 map of
# 300-point curves (16 384 fits): its size and how long Chromium takes to
# open it (`make bench-report`; reported, not asserted).
LF=${1:?usage: sh tests/bench/report.sh path/to/layerfit}
top=$(cd "$(dirname "$0")/../.." && pwd)
chrome=$(command -v chromium || command -v chromium-browser) || { echo "chromium not found"; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$LF" map --synthetic "$tmp/big" --size 128 --points 300 --seed 5 >/dev/null 2>&1 || exit 1
/usr/bin/time -f "fit --batch --report: %e s, peak %M kB" "$LF" fit --batch "$tmp/big/plan.csv" \
    --out "$tmp/r.csv" --report "$tmp/map.html" --model thin --intervals linear --quiet || exit 1
for i in 1 2 3; do
    node "$top/tests/bench/report_load.js" "$chrome" "$tmp/map.html" || exit 1
done
