# symbols.sh: the library exports only lf_ names.  Every global symbol
# defined by the library's objects from src/ must start with "lf_" (helpers
# shared between files are prefixed and declared in an internal header,
# the rest static).  fit/ objects are left out for now (their fit_ helpers
# are being renamed with the fit core); their count is printed.
. "$(dirname "$0")/common"

lib="$(dirname "$LF")/liblayerfit.a"
if ! command -v nm >/dev/null 2>&1; then
    echo "skipped: nm not found"; summary; exit $?
fi
if [ ! -f "$lib" ]; then bad "no $lib"; summary; exit 1; fi
fitobjs=" $(cd "$top/fit" && ls *.c | sed 's/\.c$/.o/' | tr '\n' ' ') "
nm -g --defined-only "$lib" >"$tmp/nm" 2>"$tmp/nmerr" || bad "nm failed: $(cat "$tmp/nmerr")"
# lines: "lib.a[obj.o]:" or "obj.o:" headers, then "ADDR T name"
awk -v fit="$fitobjs" '
    /:$/ { obj = $0; sub(/:$/, "", obj); sub(/.*\[/, "", obj); sub(/\]$/, "", obj); next }
    NF == 3 && $2 ~ /^[TDRBVWGSC]$/ {
        where = index(fit, " " obj " ") ? "fit" : "src"
        print where, obj, $3
    }' "$tmp/nm" >"$tmp/syms"
n=$(grep -c '^src ' "$tmp/syms")
if [ "$n" -gt 20 ]; then ok; else bad "only $n symbols read from the src/ objects"; fi
# names starting with "__" are the compiler's (e.g. __odr_asan.* under ASan)
grep '^src ' "$tmp/syms" | awk '$3 !~ /^lf_/ && $3 !~ /^__/' >"$tmp/badsyms"
if [ -s "$tmp/badsyms" ]; then
    bad "src/ objects export names without the lf_ prefix:"
    sed 's/^src /  /' "$tmp/badsyms"
else
    ok
fi
# and every lf_ name is declared in a header of src/ (public or internal)
undeclared=""
for s in $(grep '^src ' "$tmp/syms" | awk '$3 ~ /^lf_/ { print $3 }' | sort -u); do
    grep -qw -- "$s" "$top"/src/*.h || undeclared="$undeclared $s"
done
if [ -z "$undeclared" ]; then ok; else bad "exported but declared in no header of src/:$undeclared"; fi
nfit=$(grep '^fit ' "$tmp/syms" | awk '$3 !~ /^lf_/ && $3 !~ /^__/' | wc -l)
echo "note: fit/ objects export $nfit names without the lf_ prefix (not checked here)"
summary
