# example.sh: the README's library example, built against the installed
# header, libraries (shared and static) and pkg-config file (make install
# DESTDIR=... PREFIX=/usr).
. "$(dirname "$0")/common"
top=$(cd "$(dirname "$0")/../.." && pwd)
build=$(basename "$(dirname "$LF")")
if ! command -v pkg-config >/dev/null 2>&1; then
    echo "note: pkg-config is not installed (apt-get install pkgconf); example not built"
    summary; exit
fi
dest="$tmp/root"
# a sanitizer build (make sanitize) is installed with its own flags, so
# that whatever make rebuilds matches the rest of it
san=""
if nm "$top/$build/liblayerfit.a" 2>/dev/null | grep -q __asan_; then
    san="-fsanitize=address,undefined"
    set -- SANFLAGS="-fsanitize=address,undefined -fno-sanitize-recover=all" \
           OPT="-O1 -g -fno-omit-frame-pointer"
else
    set --
fi
(unset MAKEFLAGS MFLAGS MAKELEVEL; make -s -C "$top" install BUILD="$build" DESTDIR="$dest" PREFIX=/usr "$@") \
    >"$tmp/make.log" 2>&1 && ok || { bad "make install: $(tail -n 5 "$tmp/make.log")"; summary; exit; }
for f in usr/bin/layerfit usr/lib/liblayerfit.a usr/include/layerfit.h \
         usr/lib/pkgconfig/layerfit.pc usr/share/man/man1/layerfit.1; do
    [ -f "$dest/$f" ] && ok || bad "installed $f"
done
# the shared library, versioned, with its soname's link and the link for -l
so=$(cd "$dest/usr/lib" && ls liblayerfit.so.*.*.* 2>/dev/null | head -n 1)
[ -n "$so" ] && [ -f "$dest/usr/lib/$so" ] && ok || bad "installed liblayerfit.so.MAJOR.MINOR.PATCH"
[ -L "$dest/usr/lib/liblayerfit.so" ] && [ -f "$dest/usr/lib/liblayerfit.so" ] && ok \
    || bad "installed the link liblayerfit.so"
# one header, the public one: what only the command uses is not installed
[ "$(ls "$dest/usr/include")" = "layerfit.h" ] && ok || bad "installed headers: $(ls "$dest/usr/include")"
flags=$(PKG_CONFIG_PATH= PKG_CONFIG_LIBDIR="$dest/usr/lib/pkgconfig" PKG_CONFIG_SYSROOT_DIR="$dest" \
        pkg-config --cflags --libs layerfit) && ok || bad "pkg-config finds layerfit"
case "$flags" in *"-I$dest/usr/include"*) ok ;; *) bad "pkg-config flags point into DESTDIR: $flags" ;; esac
# (a sanitizer build's library needs the sanitizer runtime in the program)
# shellcheck disable=SC2086
${CC:-cc} -std=c11 -Wall -Wextra -Werror $san -o "$tmp/example" "$top/tests/example/example.c" $flags \
    2>"$tmp/cc.err" && ok || bad "example builds: $(head -n 5 "$tmp/cc.err")"
# linked to the shared library (the one in DESTDIR, not any other)
if objdump -p "$tmp/example" 2>/dev/null | grep -q 'NEEDED *liblayerfit\.so'; then ok
else bad "the example is not linked to liblayerfit.so"; fi
(cd "$top" && LD_LIBRARY_PATH="$dest/usr/lib" "$tmp/example" datasets/plan.csv) >"$tmp/out" 2>"$tmp/err" \
    && ok || bad "example runs: $(cat "$tmp/err")"
# and to the static one, with the libraries pkg-config names
static=$(PKG_CONFIG_PATH= PKG_CONFIG_LIBDIR="$dest/usr/lib/pkgconfig" PKG_CONFIG_SYSROOT_DIR="$dest" \
         pkg-config --libs-only-l layerfit | sed 's/-llayerfit//')
# shellcheck disable=SC2086
${CC:-cc} -std=c11 -Wall -Wextra -Werror $san -I"$dest/usr/include" -o "$tmp/example-static" \
    "$top/tests/example/example.c" "$dest/usr/lib/liblayerfit.a" $static 2>"$tmp/cc.err" && ok \
    || bad "example builds statically: $(head -n 5 "$tmp/cc.err")"
(cd "$top" && "$tmp/example-static" datasets/plan.csv) >"$tmp/out-static" 2>"$tmp/err" && ok \
    || bad "static example runs: $(cat "$tmp/err")"
cmp -s "$tmp/out" "$tmp/out-static" && ok || bad "static and shared examples differ"
has "example converged" "$tmp/out" "converged: yes"
near "example w (datasets truth 12.3 mJ/m^2)" "$(sed -n 's/^w  = \([^ ]*\) .*/\1/p' "$tmp/out")" 0.0123 0.05
near "example E* (truth 1.85 GPa)" "$(sed -n 's/^E\* = \([^ ]*\) .*/\1/p' "$tmp/out")" 1.85e9 0.02
has "example lists the curves" "$tmp/out" "curve 4: pull-off force"
# the README quotes the example as it is: every line, indented by 4
if [ -f "$top/README.md" ]; then
    missing=$(sed 's/^/    /; s/^ *$//' "$top/tests/example/example.c" | while IFS= read -r l; do
        [ -z "$l" ] && continue; grep -qxF -- "$l" "$top/README.md" || echo "$l"; done | head -n 3)
    [ -z "$missing" ] && ok || bad "README does not quote tests/example/example.c: $missing"
fi
# the Python package installed beside the libraries, found from anywhere
# through its link to the installed shared library (a sanitizer build's
# library needs its runtime preloaded: run.sh's Python tests cover it)
py="$dest/usr/lib/python3/dist-packages"
[ -f "$py/layerfit/__init__.py" ] && [ -f "$py/layerfit/liblayerfit.so.0" ] && ok \
    || bad "installed the Python package and its link to the library"
if [ -z "$san" ] && [ -x /usr/bin/python3 ]; then
    (cd "$tmp" && env -u LAYERFIT_LIBRARY PYTHONPATH="$py" PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -c "
import layerfit
print(layerfit.library_path)
r = layerfit.fit('$top/datasets/plan.csv')
print('converged' if r.converged else 'not converged', r.w.value)") >"$tmp/py.out" 2>"$tmp/py.err" \
        && ok || bad "installed Python package: $(tail -n 3 "$tmp/py.err")"
    has "python finds the installed library" "$tmp/py.out" "$py/layerfit/liblayerfit.so.0"
    has "python fits from the install" "$tmp/py.out" "converged"
fi
summary
