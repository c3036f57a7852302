# manpage.sh: the man page (src/layerfit.1) documents every command and
# every option that a command's --help lists, and roff reads it without a
# warning.
. "$(dirname "$0")/common"

man="$top/src/layerfit.1"
for c in model check fit "fit --batch" simulate map design bench cache; do
    # shellcheck disable=SC2086
    "$LF" $c --help >"$tmp/help" 2>&1 || { bad "layerfit $c --help: exit $?"; continue; }
    for o in $(grep -oE -- '--[a-z][a-z0-9-]*' "$tmp/help" | sort -u); do
        esc=$(printf '%s' "$o" | sed 's/-/\\\\-/g')
        grep -q -- "$esc" "$man" && ok || bad "man page lacks $c $o (listed by '$c --help')"
    done
    name=${c%% *}
    grep -q "^\.SS $name" "$man" && ok || bad "man page has no section for $name"
done
if command -v groff >/dev/null 2>&1; then
    groff -man -Tutf8 -ww -z "$man" 2>"$tmp/err"
    [ ! -s "$tmp/err" ] && ok || bad "roff warnings: $(head -3 "$tmp/err")"
fi
summary
