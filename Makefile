# layerfit: plain Makefile.  `make demo` and `make check` are the two
# commands of the README; both install missing Debian packages first.

PREFIX  ?= /usr/local
BINDIR  ?= $(PREFIX)/bin
LIBDIR  ?= $(PREFIX)/lib
INCDIR  ?= $(PREFIX)/include
MANDIR  ?= $(PREFIX)/share/man
PKGDIR  ?= $(LIBDIR)/pkgconfig
# the Python package (src/python/layerfit): Debian's /usr/bin/python3 looks
# in /usr/lib/python3/dist-packages and /usr/local/lib/python3/dist-packages
PYDIR   ?= $(LIBDIR)/python3/dist-packages
BUILD   ?= build

CC      ?= cc
WARN    := -Wall -Wextra -Wpedantic -Wshadow -Wpointer-arith -Wstrict-prototypes \
           -Wmissing-prototypes -Wformat=2 -Wundef
ifeq ($(WERROR),1)
WARN    += -Werror
endif
OPT     ?= -O3 -funroll-loops -g
# project flags first, the user's CFLAGS after them
OPENMP  ?= -fopenmp
# HAVE_INLINE: GSL's element accessors (gsl_vector_get, ...) inline, range
# checks kept
ALL_CFLAGS := -std=c11 -D_DEFAULT_SOURCE -DHAVE_INLINE $(WARN) $(OPT) $(OPENMP) $(SANFLAGS) -Isrc -Ifit $(CFLAGS)
LDLIBS  := -lgsl -lgslcblas -lcsv -ludunits2 -lnettle -lz -lpthread -lm
ALL_LDFLAGS := $(OPENMP) $(SANFLAGS) $(LDFLAGS)

# the command (src/cli/) is built on the library's public header
CLI_SRC := $(wildcard src/cli/*.c)
LIB_SRC := $(wildcard src/*.c) $(wildcard fit/*.c)
LIB_OBJ := $(LIB_SRC:%.c=$(BUILD)/%.o)
CLI_OBJ := $(CLI_SRC:%.c=$(BUILD)/%.o)
TEST_SRC := $(wildcard tests/test_*.c)
TEST_BIN := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
HEADERS := $(wildcard src/*.h src/cli/*.h fit/*.h) tests/testlib.h

VERSION := $(shell sed -n 's/^\#define LF_VERSION "\(.*\)"/\1/p' src/layerfit.h)
SONAME  := liblayerfit.so.$(firstword $(subst ., ,$(VERSION)))
PYSRC   := $(wildcard src/python/layerfit/*.py)
# the installed libraries, static and shared: they export exactly what
# src/layerfit.h declares (LF_API; tests/cli/symbols.sh checks)
LIB  := $(BUILD)/liblayerfit.a
SO   := $(BUILD)/liblayerfit.so.$(VERSION)
# every object with every symbol, for the command, the tests, the benches
# and the fuzzers (not installed)
LIB_ALL := $(BUILD)/liblayerfit-internal.a
PROG := $(BUILD)/layerfit

DEBS := libgsl-dev libcsv-dev libudunits2-dev nettle-dev zlib1g-dev gnuplot-nox python3-pytest
# wanted by some tests (the browser test drives headless Chromium from
# node, the example test uses pkg-config, `layerfit bench` runs the
# scipy and lmfit peers, the Python package gives numpy arrays and draws
# with matplotlib), which skip with a note
# when they are missing: installed when possible, never required
OPT_DEBS := chromium pkgconf python3-scipy python3-lmfit python3-numpy python3-matplotlib
# puppeteer-core for the browser test (tests/cli/browser.sh), from npm at the
# versions of tests/browser/package-lock.json, into tests/browser/node_modules
# (Debian's nodejs and npm first where there is no npm)
BROWSER_MODULES := tests/browser/node_modules/puppeteer-core/package.json

.PHONY: all deps demo check tests sanitize install uninstall clean bench-batch bench-demo bench bench-quick coverage

all: $(PROG) $(LIB) $(SO)

# The library's objects are position-independent (they make the shared
# library too) and hide every symbol but those layerfit.h marks LF_API.
$(BUILD)/%.o: %.c $(HEADERS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -fPIC -fvisibility=hidden -c $< -o $@

# The command sees the library's headers only, as it would installed ones:
# build/include holds copies of src/layerfit.h and of src/command.h (what
# the command shares with the library beyond the public interface; not
# installed), and src/ and fit/ are not on the command's include path.
CLI_CFLAGS := $(filter-out -Isrc -Ifit,$(ALL_CFLAGS)) -I$(BUILD)/include
$(BUILD)/include/%.h: src/%.h
	@mkdir -p $(dir $@)
	cp $< $@

$(BUILD)/src/cli/%.o: src/cli/%.c $(BUILD)/include/layerfit.h $(BUILD)/include/command.h \
                      $(wildcard src/cli/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CLI_CFLAGS) -c $< -o $@

$(LIB_ALL): $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

# the static library: one relocatable object whose hidden symbols are made
# local, so that it too exports the public interface alone
$(LIB): $(LIB_OBJ)
	@rm -f $@ $(BUILD)/liblayerfit.o
	$(CC) -r -nostdlib -o $(BUILD)/liblayerfit.o $^
	objcopy --localize-hidden $(BUILD)/liblayerfit.o
	ar rcs $@ $(BUILD)/liblayerfit.o

# the shared library, for other languages' bindings: soname
# liblayerfit.so.MAJOR, with the links liblayerfit.so.MAJOR and
# liblayerfit.so beside it
$(SO): $(LIB_OBJ)
	$(CC) -shared $(SANFLAGS) $(LDFLAGS) -Wl,-soname,$(SONAME) -Wl,-z,defs -o $@ $^ $(LDLIBS)
	ln -sf $(notdir $@) $(BUILD)/$(SONAME)
	ln -sf $(SONAME) $(BUILD)/liblayerfit.so

# The report's script and style (src/cli/page.js, page.css) as C arrays,
# embedded into the command (cli/page.c writes them into every page).
PAGE_ASSETS := $(BUILD)/src/cli/page_assets.o
$(BUILD)/src/cli/page_assets.c: src/cli/page.js src/cli/page.css
	@mkdir -p $(dir $@)
	@{ echo '/* made by the Makefile from src/cli/page.js and page.css */'; \
	  echo '#include <stddef.h>'; \
	  for v in js css; do \
	    echo "extern const unsigned char cli_page_$$v[]; extern const size_t cli_page_$${v}_len;"; \
	    echo "const unsigned char cli_page_$$v[] = {"; \
	    od -An -v -tx1 src/cli/page.$$v | sed 's/\([0-9a-f][0-9a-f]\)/0x\1,/g'; \
	    echo '0 };'; \
	    echo "const size_t cli_page_$${v}_len = sizeof cli_page_$$v - 1;"; \
	  done; } > $@.tmp && mv $@.tmp $@
$(PAGE_ASSETS): $(BUILD)/src/cli/page_assets.c
	$(CC) $(CLI_CFLAGS) -c $< -o $@

$(PROG): $(CLI_OBJ) $(PAGE_ASSETS) $(LIB_ALL)
	$(CC) $(ALL_LDFLAGS) -o $@ $(CLI_OBJ) $(PAGE_ASSETS) $(LIB_ALL) $(LDLIBS)

$(BUILD)/tests/%: tests/%.c tests/testlib.c tests/scene.c $(LIB_ALL) $(HEADERS) tests/scene.h
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -Itests $(ALL_LDFLAGS) -o $@ $< tests/testlib.c tests/scene.c $(LIB_ALL) $(LDLIBS)

# the layout of the structures the Python package mirrors (tests/python)
$(BUILD)/tests/python_abi: tests/python/abi.c src/layerfit.h
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -o $@ $<

# the symbol test reads the installed libraries' symbols
tests: $(TEST_BIN) $(PROG) $(LIB) $(SO) $(BUILD)/tests/python_abi

# Install what is missing (as root), or say the exact command to run.
deps:
	@missing=""; for p in $(DEBS); do \
	  dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "installing:$$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null || exit 1; \
	  else \
	    echo "layerfit needs:$$missing"; \
	    echo "run: sudo apt-get install -y$$missing"; exit 1; \
	  fi; \
	fi; \
	optional=""; for p in $(OPT_DEBS); do \
	  dpkg -s $$p >/dev/null 2>&1 || optional="$$optional $$p"; done; \
	if [ -n "$$optional" ] && [ "$$(id -u)" = 0 ]; then \
	  echo "installing (optional, for tests):$$optional"; \
	  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$optional >/dev/null) \
	    || echo "could not install$$optional: the tests that use them will say so and skip"; \
	fi; \
	if [ ! -f $(BROWSER_MODULES) ]; then \
	  if ! command -v npm >/dev/null 2>&1 && [ "$$(id -u)" = 0 ]; then \
	    echo "installing (optional, for the browser test): nodejs npm"; \
	    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nodejs npm >/dev/null) \
	      || echo "could not install nodejs npm: the browser test will say so"; \
	  fi; \
	  if command -v npm >/dev/null 2>&1; then \
	    echo "installing puppeteer-core (npm ci in tests/browser)"; \
	    (cd tests/browser && npm ci --no-audit --no-fund --loglevel=error >/dev/null) \
	      || echo "could not install puppeteer-core: the browser test will fail"; \
	  fi; \
	fi

demo: deps
	@$(MAKE) --no-print-directory all
	@sh tests/demo.sh $(PROG)

check: deps
	@$(MAKE) --no-print-directory tests
	@sh tests/run.sh $(BUILD)

sanitize: deps
	@$(MAKE) --no-print-directory BUILD=build-san OPT="-O1 -g -fno-omit-frame-pointer" \
	  SANFLAGS="-fsanitize=address,undefined -fno-sanitize-recover=all" tests
	@ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$(LSAN_SUPP) \
	  UBSAN_OPTIONS=print_stacktrace=1 sh tests/run.sh build-san

# Throughput and peak memory of `fit --batch` on 16 384 synthetic curves
# of 300 points (reported, not asserted).
bench-batch: all
	@sh tests/bench/batch.sh $(PROG)

# The map report of 16 384 curves: its size and how long Chromium takes to
# open it (reported, not asserted).
.PHONY: bench-report
bench-report: all
	@sh tests/bench/report.sh $(PROG)

# The whole process: `fit --model auto` on the demo against `--model thin`
# (alternated runs, medians), and one cold run (reported, not asserted).
bench-demo: all
	@sh tests/bench/demo_ratio.sh $(PROG)

# How often the 95% intervals hold the truth over 200 seeds, and the RMS
# error over the Cramer-Rao bound (reported; a 40-seed version is asserted
# in tests/cli/honest.sh).
coverage: all
	$(PROG) bench --coverage --seeds 200

$(BUILD)/layerfit.pc: src/layerfit.pc.in
	@mkdir -p $(dir $@)
	sed -e 's|@PREFIX@|$(PREFIX)|g' -e 's|@LIBDIR@|$(LIBDIR)|g' \
	    -e 's|@INCDIR@|$(INCDIR)|g' -e 's|@VERSION@|$(VERSION)|g' $< > $@

install: all $(BUILD)/layerfit.pc
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(INCDIR) $(DESTDIR)$(PKGDIR) $(DESTDIR)$(MANDIR)/man1
	install -m 755 $(PROG) $(DESTDIR)$(BINDIR)/layerfit
	install -m 644 $(LIB) $(DESTDIR)$(LIBDIR)/liblayerfit.a
	install -m 755 $(SO) $(DESTDIR)$(LIBDIR)/liblayerfit.so.$(VERSION)
	ln -sf liblayerfit.so.$(VERSION) $(DESTDIR)$(LIBDIR)/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(LIBDIR)/liblayerfit.so
	install -m 644 src/layerfit.h $(DESTDIR)$(INCDIR)/layerfit.h
	install -m 644 $(BUILD)/layerfit.pc $(DESTDIR)$(PKGDIR)/layerfit.pc
	install -m 644 src/layerfit.1 $(DESTDIR)$(MANDIR)/man1/layerfit.1
	install -d $(DESTDIR)$(PYDIR)/layerfit
	install -m 644 $(PYSRC) $(DESTDIR)$(PYDIR)/layerfit/
	ln -sf "$$(realpath -m --relative-to=$(PYDIR)/layerfit $(LIBDIR)/$(SONAME))" \
	    $(DESTDIR)$(PYDIR)/layerfit/$(SONAME)

uninstall:
	rm -f $(DESTDIR)$(BINDIR)/layerfit $(DESTDIR)$(LIBDIR)/liblayerfit.a \
	      $(DESTDIR)$(LIBDIR)/liblayerfit.so.$(VERSION) $(DESTDIR)$(LIBDIR)/$(SONAME) \
	      $(DESTDIR)$(LIBDIR)/liblayerfit.so \
	      $(DESTDIR)$(INCDIR)/layerfit.h $(DESTDIR)$(PKGDIR)/layerfit.pc \
	      $(DESTDIR)$(MANDIR)/man1/layerfit.1
	rm -rf $(DESTDIR)$(PYDIR)/layerfit

clean:
	rm -rf build build-san build-fuzz

# Longer recovery Monte Carlo (2000 seeds per scene), on demand.
.PHONY: recovery-long bench-fit
recovery-long: $(BUILD)/tests/test_recovery
	$(BUILD)/tests/test_recovery 2000

# Timing of a two-probe joint fit against scipy (reported, not asserted).
$(BUILD)/bench_fit: tests/bench/bench_fit.c $(LIB_ALL) $(HEADERS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(ALL_LDFLAGS) -o $@ $< $(LIB_ALL) $(LDLIBS)

bench-fit: $(BUILD)/bench_fit
	@mkdir -p $(BUILD)/bench
	$(BUILD)/bench_fit $(BUILD)/bench

# Fuzzing with clang's libFuzzer: `make fuzz` runs each target for
# FUZZ_SECONDS seconds from the seeds in tests/fuzz/TARGET, keeping what it
# learns in build-fuzz/corpus.  A crash stops it and leaves the input in
# build-fuzz/; keep such inputs in tests/fuzz/regress (replayed by
# tests/test_fuzz_regress.c).
FUZZ_SECONDS ?= 20
# known leaks of third-party libraries (libudunits2), not layerfit's
LSAN_SUPP := $(CURDIR)/tests/fuzz/lsan.supp
FUZZ_CC ?= clang
FUZZ_TARGETS := curve plan design chiaro jpk workshop ntmdt hysitron text tab jpk_force \
                workshop_map nanoscope igor
FUZZ_SAN := -fsanitize=address,undefined -fno-sanitize-recover=all

.PHONY: fuzz fuzz-build
fuzz-build:
	@$(MAKE) --no-print-directory BUILD=build-fuzz CC=$(FUZZ_CC) OPT="-O1 -g" OPENMP= \
	  SANFLAGS="-fsanitize=fuzzer-no-link $(FUZZ_SAN)" build-fuzz/liblayerfit-internal.a
	@for t in $(FUZZ_TARGETS); do \
	  $(FUZZ_CC) -std=c11 -D_DEFAULT_SOURCE -O1 -g -fsanitize=fuzzer $(FUZZ_SAN) \
	    -Isrc -Itests -o build-fuzz/fuzz_$$t tests/fuzz/fuzz_$$t.c build-fuzz/liblayerfit-internal.a \
	    $(LDLIBS) || exit 1; \
	done

fuzz: fuzz-build
	@for t in $(FUZZ_TARGETS); do \
	  mkdir -p build-fuzz/corpus/$$t; \
	  LSAN_OPTIONS=suppressions=$(LSAN_SUPP) build-fuzz/fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
	    -artifact_prefix=build-fuzz/$$t- build-fuzz/corpus/$$t tests/fuzz/$$t \
	    >build-fuzz/fuzz_$$t.log 2>&1; rc=$$?; \
	  runs=$$(sed -n 's/^stat::number_of_executed_units: *//p' build-fuzz/fuzz_$$t.log); \
	  echo "fuzz_$$t: $${runs:-?} executions in $(FUZZ_SECONDS) s, exit $$rc"; \
	  if [ $$rc -ne 0 ]; then grep -A30 -E '^==[0-9]+==ERROR|deadly signal' build-fuzz/fuzz_$$t.log | head -60; \
	    ls build-fuzz/$$t-* 2>/dev/null; exit 1; fi; \
	done

# Reading a large file of many curves (a synthetic 256 x 256 QI map)
# against `unzip -p`, and the peak memory of `fit --batch` over maps of
# 1024 to 16 384 curves (reported, not asserted; tests/bench/maps.sh).
$(BUILD)/bench_read: tests/bench/bench_read.c $(LIB_ALL) $(HEADERS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(ALL_LDFLAGS) -o $@ $< $(LIB_ALL) $(LDLIBS)

.PHONY: bench-maps
bench-maps: $(PROG) $(BUILD)/bench_read
	@sh tests/bench/maps.sh $(PROG) $(BUILD)/bench_read

# Speed against error of the exact model (not part of `make check`).
$(BUILD)/tests/bench/bench_exact: tests/bench/bench_exact.c $(LIB_ALL) $(HEADERS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(ALL_LDFLAGS) -o $@ $< $(LIB_ALL) $(LDLIBS)

.PHONY: bench-exact
bench-exact: $(BUILD)/tests/bench/bench_exact
	$(BUILD)/tests/bench/bench_exact

# Fit time and error of the exact model against the thin one (not part of
# `make check`).
$(BUILD)/tests/bench/bench_models: tests/bench/bench_models.c $(LIB_ALL) $(HEADERS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(ALL_LDFLAGS) -o $@ $< $(LIB_ALL) $(LDLIBS)

.PHONY: bench-models
bench-models: $(BUILD)/tests/bench/bench_models
	$(BUILD)/tests/bench/bench_models

# What a fit costs and how accurate it is (`layerfit bench`): the quick run
# takes seconds (CI runs it), the full one a few minutes.
bench-quick: $(PROG)
	$(PROG) bench --quick --csv $(BUILD)/bench-quick.csv

bench: $(PROG)
	$(PROG) bench --csv $(BUILD)/bench.csv --plot $(BUILD)/bench.svg

# What a call from Python costs over the same fit inside C: a 300-point
# single-curve fit through layerfit.fit() against bench_call (reported,
# not asserted; tests/bench/python_overhead.py).
$(BUILD)/bench_call: tests/bench/bench_call.c $(SO) src/layerfit.h
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(ALL_LDFLAGS) -o $@ $< -L$(BUILD) -llayerfit -Wl,-rpath,$(CURDIR)/$(BUILD) \
	    -lgsl -lgslcblas

.PHONY: bench-python
bench-python: all $(BUILD)/bench_call
	/usr/bin/python3 tests/bench/python_overhead.py $(BUILD)

# The cost of one thin-model evaluation over 300 points (not part of
# `make check`).
$(BUILD)/tests/bench/bench_thin: tests/bench/bench_thin.c $(LIB_ALL) $(HEADERS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(ALL_LDFLAGS) -o $@ $< $(LIB_ALL) $(LDLIBS)

.PHONY: bench-thin
bench-thin: $(BUILD)/tests/bench/bench_thin
	$(BUILD)/tests/bench/bench_thin
