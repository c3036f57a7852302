# callgraph.sh: calls go one way between files.  From the defined and the
# undefined global symbols of each object (nm), the file-level call graph
# is built among the fit/ objects and among the src/cli/ objects, and a
# cycle in either (a file that calls, through any chain, back into one of
# its callers) fails, printed with the symbol of each step.
. "$(dirname "$0")/common"

build=$(cd "$(dirname "$LF")" && pwd)
if ! command -v nm >/dev/null 2>&1; then
    echo "skipped: nm not found"; summary; exit $?
fi

# graph DIR: one line "FROM TO SYMBOL" per call from one object of DIR to
# another, then the cycles found (if any), each as "cycle: a -> b (sym) -> a"
graph() {
    dir=$1; name=$2
    set -- "$build/$dir"/*.o
    if [ ! -f "$1" ]; then bad "no objects in $build/$dir"; return; fi
    for o in "$@"; do
        f=$(basename "$o" .o)
        nm -g --defined-only "$o" | awk -v f="$f" 'NF == 3 { print "D", f, $3 }'
        nm -u "$o" | awk -v f="$f" '{ print "U", f, $NF }'
    done >"$tmp/$name.sym"
    awk '
        $1 == "D" { def[$3] = $2; next }
        { use[++n] = $2 " " $3 }
        END {
            for (i = 1; i <= n; i++) {
                split(use[i], u, " ")
                if ((u[2] in def) && def[u[2]] != u[1]) {
                    e = u[1] " " def[u[2]]
                    if (!(e in why)) { why[e] = u[2]; adj[u[1]] = adj[u[1]] " " def[u[2]]; nodes[u[1]] = 1 }
                    edges++
                }
            }
            print "edges", edges + 0
            # depth-first search with colours: 1 on the path, 2 done
            for (s in nodes) if (!(s in colour)) visit(s)
        }
        function visit(v,    k, m, t, w, i, c) {
            colour[v] = 1; path[++depth] = v
            m = split(adj[v], t, " ")
            for (k = 1; k <= m; k++) {
                w = t[k]
                if ((w in colour) && colour[w] == 1) {
                    for (i = 1; path[i] != w; i++) ;
                    c = "cycle:"
                    for (; i <= depth; i++)
                        c = c " " path[i] " -> " (i < depth ? path[i + 1] : w) " (" why[path[i] " " (i < depth ? path[i + 1] : w)] ");"
                    print c
                } else if (!(w in colour)) visit(w)
            }
            depth--; colour[v] = 2
        }' "$tmp/$name.sym" >"$tmp/$name.out"
    edges=$(sed -n 's/^edges //p' "$tmp/$name.out")
    if [ "${edges:-0}" -ge 10 ]; then ok; else bad "$dir: only ${edges:-0} calls between files found"; fi
    if grep -q '^cycle:' "$tmp/$name.out"; then
        bad "$dir: calls go round in a cycle:"
        grep '^cycle:' "$tmp/$name.out" | sed 's/^/  /'
    else
        ok
    fi
}

graph fit fit
graph src/cli cli
summary
