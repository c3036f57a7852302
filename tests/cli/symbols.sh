# symbols.sh: the installed libraries export exactly what the installed
# header declares.  The functions and tables src/layerfit.h declares (the
# header `make install` installs, read through the preprocessor) are
# compared with the symbols the shared library exports (nm -D) and with the
# global symbols the static library defines (nm): any name in one list and
# not the other fails, printed.  And every global name of the library's
# objects (the command's and the tests' archive) carries the lf_ prefix.
. "$(dirname "$0")/common"

dir=$(dirname "$LF")
if ! command -v nm >/dev/null 2>&1; then
    echo "skipped: nm not found"; summary; exit $?
fi
so=$(ls "$dir"/liblayerfit.so.*.*.* 2>/dev/null | head -n 1)
for f in "$dir/liblayerfit.a" "$so" "$dir/liblayerfit-internal.a"; do
    [ -n "$f" ] && [ -f "$f" ] && ok || { bad "no library ${f:-$dir/liblayerfit.so.X.Y.Z}"; summary; exit 1; }
done

# the header's declarations: functions (the name before the parameter
# list) and tables (extern data), struct and enum bodies removed
${CC:-cc} -E -P -DLF_API= -x c "$top/src/layerfit.h" 2>"$tmp/cpp.err" | awk '
    { text = text " " $0 }
    END {
        while (gsub(/\{[^{}]*\}/, "", text)) ;
        n = split(text, decl, ";")
        for (i = 1; i <= n; i++) {
            d = decl[i]
            if (d ~ /^[ \t]*(typedef|enum|struct|union)[ \t]/ || d !~ /[A-Za-z_]/) continue
            if (match(d, /[A-Za-z_][A-Za-z_0-9]*[ \t]*\(/) && d !~ /\([ \t]*\*/) {
                name = substr(d, RSTART, RLENGTH); sub(/[ \t]*\($/, "", name); print name
            } else if (d ~ /^[ \t]*extern[ \t]/) {
                sub(/[ \t]*(\[[^]]*\])?[ \t]*$/, "", d); sub(/.*[^A-Za-z_0-9]/, "", d); print d
            }
        }
    }' | sort -u >"$tmp/declared"
n=$(wc -l <"$tmp/declared")
if [ "$n" -gt 50 ]; then ok; else bad "only $n declarations read from layerfit.h: $(cat "$tmp/cpp.err")"; fi

# what each library exports (names starting with "_" are the toolchain's
# or the sanitizers')
nm -D --defined-only "$so" | awk 'NF == 3 && $2 ~ /^[TDRBVWGSi]$/ && $3 !~ /^_/ { print $3 }' \
    | sort -u >"$tmp/so"
nm -g --defined-only "$dir/liblayerfit.a" | awk 'NF == 3 && $2 ~ /^[TDRBVWGSC]$/ && $3 !~ /^_/ { print $3 }' \
    | sort -u >"$tmp/a"
for lib in so a; do
    comm -13 "$tmp/declared" "$tmp/$lib" >"$tmp/extra"
    comm -23 "$tmp/declared" "$tmp/$lib" >"$tmp/missing"
    if [ -s "$tmp/extra" ]; then
        bad "liblayerfit.$lib exports $(wc -l <"$tmp/extra") names layerfit.h does not declare:"
        sed 's/^/  /' "$tmp/extra" | head -n 40
    else ok; fi
    if [ -s "$tmp/missing" ]; then
        bad "liblayerfit.$lib does not export $(wc -l <"$tmp/missing") names layerfit.h declares:"
        sed 's/^/  /' "$tmp/missing" | head -n 40
    else ok; fi
done
echo "note: layerfit.h declares $n names; liblayerfit.so exports $(wc -l <"$tmp/so"), liblayerfit.a $(wc -l <"$tmp/a")"

# the shared library's name: soname liblayerfit.so.MAJOR, links beside it
soname=$(objdump -p "$so" 2>/dev/null | awk '$1 == "SONAME" { print $2 }')
case "$soname" in liblayerfit.so.[0-9]*) ok ;; *) bad "soname '$soname', want liblayerfit.so.MAJOR" ;; esac
[ "$(readlink "$dir/$soname")" = "$(basename "$so")" ] && ok || bad "$soname does not link to $(basename "$so")"
[ "$(readlink "$dir/liblayerfit.so")" = "$soname" ] && ok || bad "liblayerfit.so does not link to $soname"

# every global name of the library's objects is lf_-prefixed
nm -g --defined-only "$dir/liblayerfit-internal.a" \
    | awk 'NF == 3 && $2 ~ /^[TDRBVWGSC]$/ && $3 !~ /^lf_/ && $3 !~ /^_/ { print $3 }' >"$tmp/bad"
if [ -s "$tmp/bad" ]; then
    bad "the library's objects define names without the lf_ prefix:"; sed 's/^/  /' "$tmp/bad" | head
else ok; fi
summary
