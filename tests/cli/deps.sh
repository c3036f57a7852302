# deps.sh: `make deps` when a package is missing and we are not root says
# the exact command to run (dpkg and id are stand-ins on PATH here, so
# nothing is installed).
. "$(dirname "$0")/common"

mkdir -p "$tmp/bin"
cat > "$tmp/bin/dpkg" <<'SH'
#!/bin/sh
# every package present but libcsv-dev
case "$*" in *libcsv-dev*) exit 1 ;; esac
exit 0
SH
printf '#!/bin/sh\necho 1000\n' > "$tmp/bin/id"
chmod +x "$tmp/bin/dpkg" "$tmp/bin/id"
PATH="$tmp/bin:$PATH" make -s -C "$top" deps >"$tmp/out" 2>&1; rc=$?
[ "$rc" -ne 0 ] && ok || bad "make deps fails when a package is missing and it cannot install"
has "names what is missing" "$tmp/out" "layerfit needs: libcsv-dev"
has "says the exact command" "$tmp/out" "run: sudo apt-get install -y libcsv-dev"
# nothing missing: silent success
printf '#!/bin/sh\nexit 0\n' > "$tmp/bin/dpkg"
PATH="$tmp/bin:$PATH" make -s -C "$top" deps >"$tmp/out" 2>&1 && ok || bad "make deps succeeds when nothing is missing"
grep -q "apt-get" "$tmp/out" && bad "make deps with nothing missing mentions apt-get" || ok
summary
