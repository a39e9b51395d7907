# lancer: liblancer.a (the C core), the Lua module and the lancer command.
#   make          build everything under build/
#   make demo     install missing Debian packages, build, render the showcase
#   make test     install missing Debian packages, build, run every test
#   make bench    lancer against POV-Ray, Tachyon and Embree (QUICK=1: a subset)
#   make install  install lancer, the Lua module, liblancer.a, lancer.h and
#                 lancer.pc under PREFIX (/usr/local), staged under DESTDIR
#   make uninstall  remove what make install put there
#   make SAN=1    build/san: address, undefined-behaviour and leak sanitizers
#   make santest  the tests against build/san (ASan + UBSan + LSan, any report fails)
#   make tsan     the threaded C tests under ThreadSanitizer (build/tsan)
#   make fuzz     the libFuzzer harnesses of tests/fuzz/, FUZZ_SECONDS (60) each
#   make NAIVE=1  build/naive: naive intersections and epsilons (bench only)
#   make MINIMAL=1 build/minimal: diffuse-only shading (bench only)

CC      ?= cc
FUZZ_CC ?= clang
ifeq ($(NAIVE),1)
# The textbook intersections and a fixed spawn epsilon, for pricing the robust
# code in make bench; never for rendering.
BUILD   ?= build/naive
CPPFLAGS += -DLC_NAIVE
endif
ifeq ($(MINIMAL),1)
# shade_minimal.c instead of shade.c: the diffuse path alone, for pricing
# the full shading in make bench (docs/numerics.md S7); never for rendering.
BUILD   ?= build/minimal
CPPFLAGS += -DLC_MINIMAL
endif
ifeq ($(SAN),1)
# Its own tree: make SAN=1 after a plain make rebuilds everything, and the
# two builds never mix objects.
BUILD   ?= build/san
endif
ifeq ($(TSAN),1)
BUILD   ?= build/tsan
endif
ifeq ($(FUZZ),1)
# The libFuzzer harnesses' tree (tests/fuzz/): clang, every object
# instrumented for coverage and sanitized; make fuzz and the test smoke.
BUILD   ?= build/fuzz
CC      := $(FUZZ_CC)
CFLAGS  ?= -O1 -g
endif
BUILD   ?= build
PKGS    := lua5.4 libpng
WARN    := -Wall -Wextra -Wshadow -Wundef -Wwrite-strings -Wstrict-prototypes \
           -Wmissing-prototypes -Wvla
# -ffp-contract=off: a fused a*b-c*d breaks the exact sign symmetry the
# robust geometry relies on (docs/numerics.md 1.12). Never -ffast-math.
# -O3: 6-8 % fewer instructions than -O2 on B1, B2 and B3 (callgrind), the
# same image bits on every scene tried and every test passing; the flags
# below keep IEEE arithmetic (no fused multiply-add, no fast-math).
CFLAGS  ?= -O3 -g
CFLAGS  += -std=c99 $(WARN) -ffp-contract=off -fPIC -pthread -D_POSIX_C_SOURCE=200809L
CPPFLAGS += -MMD -MP -Isrc
ifeq ($(SAN),1)
# -fno-sanitize-recover: undefined behaviour stops the program, as an ASan
# report does, so no report scrolls past a test that goes on passing.
# GCC's undefined leaves out two checks. float-cast-overflow is added: a
# floating value converted to an integer type that cannot hold it (illum
# 1e300 as an int) is undefined, and readers of files and scripts must
# refuse such values first. float-divide-by-zero is not: the core divides
# by zero on purpose for IEEE infinities (a ray's inverse direction along
# an axis it does not move on, shapes/box.c), defined in IEEE arithmetic.
SANITIZE := -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all
CFLAGS  += $(SANITIZE) -fno-omit-frame-pointer
LDFLAGS += $(SANITIZE)
# GCC's shared libubsan beside libasan ignores log_path, so its reports
# would go only to a stderr a test may swallow; linked into the programs
# (lancer, the C tests) it writes them where tests/run.sh looks.
EXE_LDFLAGS := -static-libubsan
endif
ifeq ($(TSAN),1)
CFLAGS  += -fsanitize=thread
LDFLAGS += -fsanitize=thread
endif
ifeq ($(FUZZ),1)
SANITIZE := -fsanitize=address,undefined -fno-sanitize-recover=all
CFLAGS  += -fsanitize=fuzzer-no-link $(SANITIZE) -fno-omit-frame-pointer
endif

LUA_CFLAGS := $(shell pkg-config --cflags lua5.4 2>/dev/null)
LUA_LIBS   := $(shell pkg-config --libs lua5.4 2>/dev/null)
PNG_CFLAGS := $(shell pkg-config --cflags libpng 2>/dev/null)
PNG_LIBS   := $(shell pkg-config --libs libpng 2>/dev/null)
# OpenEXR through its C library alone (OpenEXRCore, src/image/exr.c): OpenEXR.pc's
# --libs would also pull in the C++ libraries, and its --cflags need Imath.
EXR_CFLAGS := $(addprefix -I,$(shell pkg-config --variable=OpenEXR_includedir OpenEXR 2>/dev/null))
EXR_LIBS   := $(shell pkg-config --exists OpenEXR 2>/dev/null && echo \
                -L$$(pkg-config --variable=libdir OpenEXR) \
                -lOpenEXRCore$$(pkg-config --variable=libsuffix OpenEXR))
EDIT_CFLAGS := $(shell pkg-config --cflags libedit 2>/dev/null)
EDIT_LIBS   := $(shell pkg-config --libs libedit 2>/dev/null)
CMOCKA_LIBS := $(shell pkg-config --libs cmocka 2>/dev/null)
ZLIB_LIBS   := $(shell pkg-config --libs zlib 2>/dev/null)

# The C core's folders, in the order they may depend on each other (README.md,
# "Where things are"; tests/lua/test_folders.lua checks every include).
CORE_DIRS := base image texture accel shapes scene import material media tracer light render
# Lua-free helpers the binding and the command share but the core must not
# have (the core never prints): linked into the module and lancer only.
HELPER_SRC := src/lua/progress_bar.c
# The C core: no Lua header in any of these.
CORE_SRC := $(filter-out src/render/shade_minimal.c,$(foreach d,$(CORE_DIRS),$(wildcard src/$(d)/*.c)))
# The lancer command: src/cli/.
HOST_OBJ := $(patsubst src/%.c,$(BUILD)/obj/%.o,$(wildcard src/cli/*.c))
ifeq ($(MINIMAL),1)
CORE_SRC := $(filter-out src/render/shade.c,$(CORE_SRC)) src/render/shade_minimal.c
endif
CORE_OBJ := $(CORE_SRC:src/%.c=$(BUILD)/obj/%.o)
LUA_SRC  := $(filter-out $(HELPER_SRC),$(wildcard src/lua/*.c))
LUA_OBJ  := $(LUA_SRC:src/%.c=$(BUILD)/obj/%.o)
HELPER_OBJ := $(HELPER_SRC:src/%.c=$(BUILD)/obj/%.o)
LUA_FILES := $(wildcard lua/lancer/*.lua)

# Where make install puts things. The Lua module goes where the stock lua5.4
# looks under PREFIX, Lua's own layout: lua5.4.pc's INSTALL_CMOD is
# /usr/lib/<multiarch>/lua/5.4, which a PREFIX of /usr/local does not reach,
# and Debian's lua5.4 searches $(PREFIX)/lib/lua/5.4 and $(PREFIX)/share/lua/5.4
# for both /usr/local and /usr (docs/conventions.md 1).
PREFIX     ?= /usr/local
BINDIR     ?= $(PREFIX)/bin
LIBDIR     ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
LUA_LMOD   ?= $(PREFIX)/share/lua/5.4
LUA_CMOD   ?= $(PREFIX)/lib/lua/5.4
INSTALL    ?= install

LIB    := $(BUILD)/liblancer.a
MODULE := $(BUILD)/lancer/core.so
BIN    := $(BUILD)/bin/lancer
C_TESTS := $(patsubst tests/c/%.c,$(BUILD)/tests/%,$(wildcard tests/c/test_*.c))

.PHONY: all demo test check santest tsan fuzz fuzz-build fuzzers bench clean install-deps
.PHONY: install uninstall
all: $(LIB) $(MODULE) $(BIN) $(BUILD)/lancer-uninstalled.pc

$(BUILD)/obj/%.o: src/%.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(PNG_CFLAGS) $(EXR_CFLAGS) -c $< -o $@

$(BUILD)/obj/lua/%.o: src/lua/%.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(LUA_CFLAGS) -c $< -o $@

$(LIB): $(CORE_OBJ)
	@mkdir -p $(@D)
	rm -f $@ && $(AR) rcs $@ $^

# The module links no liblua: the lua5.4 binary exports the Lua API itself.
$(MODULE): $(LUA_OBJ) $(HELPER_OBJ) $(LIB)
	@mkdir -p $(@D)
	$(CC) -shared $(LDFLAGS) -o $@ $(LUA_OBJ) $(HELPER_OBJ) $(LIB) $(PNG_LIBS) $(EXR_LIBS) -lm -pthread

# The host embeds lua/lancer/*.lua so it runs from anywhere.
$(BUILD)/gen/lua_embedded.c: $(LUA_FILES) tools/embed-lua.sh
	@mkdir -p $(@D)
	sh tools/embed-lua.sh $(LUA_FILES) > $@.tmp && mv $@.tmp $@

$(HOST_OBJ): $(BUILD)/obj/%.o: src/%.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(LUA_CFLAGS) $(EDIT_CFLAGS) -c $< -o $@

$(BUILD)/obj/lua_embedded.o: $(BUILD)/gen/lua_embedded.c
	$(CC) $(CFLAGS) -c $< -o $@

$(BIN): $(HOST_OBJ) $(BUILD)/obj/lua_embedded.o $(LUA_OBJ) $(HELPER_OBJ) $(LIB)
	@mkdir -p $(@D)
	$(CC) $(LDFLAGS) $(EXE_LDFLAGS) -o $@ $^ $(LUA_LIBS) $(PNG_LIBS) $(EXR_LIBS) $(EDIT_LIBS) \
	    -lm -pthread

$(BUILD)/tests/%: tests/c/%.c $(LIB)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(EXR_CFLAGS) $(EXE_LDFLAGS) -Isrc -o $@ $< $(LIB) $(CMOCKA_LIBS) \
	    $(PNG_LIBS) \
	    $(EXR_LIBS) -lm -pthread

# What a program linking the core needs; only a static library is built, so
# the libraries it uses are in Libs, not Libs.private.
LINK_LIBS = $(PNG_LIBS) $(EXR_LIBS) -lm -pthread

# For programs built against the build tree:
#   cc prog.c $$(PKG_CONFIG_PATH=build pkg-config --cflags --libs lancer)
$(BUILD)/lancer-uninstalled.pc: Makefile
	@mkdir -p $(@D)
	printf '%s\n' 'Name: lancer' 'Description: lancer, an embeddable ray tracer (build tree)' \
	  'Version: $(shell sed -n 's/^#define LC_VERSION "\(.*\)"/\1/p' src/lancer.h)' \
	  'Cflags: -I$(abspath src)' 'Libs: $(abspath $(LIB)) $(LINK_LIBS)' > $@

install: all
	$(INSTALL) -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(INCLUDEDIR) \
	  $(DESTDIR)$(PKGCONFIGDIR) $(DESTDIR)$(LUA_LMOD)/lancer $(DESTDIR)$(LUA_CMOD)/lancer
	$(INSTALL) -m 755 $(BIN) $(DESTDIR)$(BINDIR)/lancer
	$(INSTALL) -m 644 $(LIB) $(DESTDIR)$(LIBDIR)/liblancer.a
	$(INSTALL) -m 644 src/lancer.h $(DESTDIR)$(INCLUDEDIR)/lancer.h
	$(INSTALL) -m 755 $(MODULE) $(DESTDIR)$(LUA_CMOD)/lancer/core.so
	$(INSTALL) -m 644 $(LUA_FILES) $(DESTDIR)$(LUA_LMOD)/lancer/
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$${prefix}$(patsubst $(PREFIX)%,%,$(LIBDIR))' \
	  'includedir=$${prefix}$(patsubst $(PREFIX)%,%,$(INCLUDEDIR))' '' 'Name: lancer' \
	  'Description: lancer, an embeddable ray tracer (its C core)' \
	  'Version: $(shell sed -n 's/^#define LC_VERSION "\(.*\)"/\1/p' src/lancer.h)' \
	  'Cflags: -I$${includedir}' 'Libs: -L$${libdir} -llancer $(LINK_LIBS)' \
	  > $(DESTDIR)$(PKGCONFIGDIR)/lancer.pc

uninstall:
	rm -f $(DESTDIR)$(BINDIR)/lancer $(DESTDIR)$(LIBDIR)/liblancer.a \
	  $(DESTDIR)$(INCLUDEDIR)/lancer.h $(DESTDIR)$(PKGCONFIGDIR)/lancer.pc \
	  $(DESTDIR)$(LUA_CMOD)/lancer/core.so \
	  $(addprefix $(DESTDIR)$(LUA_LMOD)/lancer/,$(notdir $(LUA_FILES)))
	-rmdir $(DESTDIR)$(LUA_CMOD)/lancer $(DESTDIR)$(LUA_LMOD)/lancer 2>/dev/null

install-deps:
	@sh tools/install-deps.sh build

demo:
	@sh tools/install-deps.sh build
	@$(MAKE) --no-print-directory all
	@mkdir -p out
	$(BIN) scenes/showcase.lua out/showcase.png
	@echo "wrote out/showcase.png"

test:
	@sh tools/install-deps.sh test
	@$(MAKE) --no-print-directory check

# The default tree's check ends with the fuzzers' smoke run (build/fuzz);
# the other trees' (SAN=1, ...) run the tests alone.
ifeq ($(BUILD),build)
FUZZ_TREE := build/fuzz
endif
check: all $(C_TESTS) $(if $(FUZZ_TREE),fuzz-build)
	@sh tests/run.sh $(BUILD) $(FUZZ_TREE)

# The whole suite against build/san: ASan, UBSan and LeakSanitizer, every
# report a failure (tests/run.sh says how).
santest:
	@sh tools/install-deps.sh test
	@$(MAKE) --no-print-directory SAN=1 check

# The C tests that use threads (renders, casts, interrupts, shared meshes)
# under ThreadSanitizer, in build/tsan; any report fails.
TSAN_TESTS := test_threads test_query test_api test_reliability
tsan:
	@$(MAKE) --no-print-directory TSAN=1 $(TSAN_TESTS:%=build/tsan/tests/%)
	@for t in $(TSAN_TESTS); do echo "== build/tsan/tests/$$t"; \
	    TSAN_OPTIONS="halt_on_error=1 exitcode=66" build/tsan/tests/$$t || exit 1; done

# ---- Fuzzing (tests/fuzz/README.md) --------------------------------------------

# The harnesses, each linked with libFuzzer against the instrumented core
# (and, for lua, the binding) of build/fuzz.
FUZZ_SECONDS ?= 60
FUZZERS := obj png lua exr hdr mtl
fuzz: fuzz-build
	@sh tests/fuzz/run.sh long build/fuzz $(FUZZ_SECONDS)

# Builds build/fuzz when clang can link a libFuzzer harness; otherwise says
# why in build/fuzz/toolchain, which the smoke run reports as a skip.
fuzz-build:
	@if sh tests/fuzz/toolchain.sh "$(FUZZ_CC)" build/fuzz; then \
	    $(MAKE) --no-print-directory FUZZ=1 fuzzers; fi

ifeq ($(FUZZ),1)
fuzzers: $(FUZZERS:%=$(BUILD)/fuzz_%)

$(BUILD)/fuzz_obj: tests/fuzz/obj/fuzz_obj.c $(LIB)
	$(CC) $(CPPFLAGS) $(CFLAGS) -fsanitize=fuzzer -Isrc -o $@ $< $(LIB) $(PNG_LIBS) \
	    $(EXR_LIBS) -lm -pthread

$(BUILD)/fuzz_png: tests/fuzz/png/fuzz_png.c $(LIB)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(PNG_CFLAGS) -fsanitize=fuzzer -Isrc -o $@ $< $(LIB) \
	    $(PNG_LIBS) $(ZLIB_LIBS) $(EXR_LIBS) -lm -pthread

$(BUILD)/fuzz_hdr: tests/fuzz/hdr/fuzz_hdr.c $(LIB)
	$(CC) $(CPPFLAGS) $(CFLAGS) -fsanitize=fuzzer -Isrc -o $@ $< $(LIB) $(PNG_LIBS) \
	    $(EXR_LIBS) -lm -pthread

$(BUILD)/fuzz_mtl: tests/fuzz/mtl/fuzz_mtl.c $(LIB)
	$(CC) $(CPPFLAGS) $(CFLAGS) -fsanitize=fuzzer -Isrc -o $@ $< $(LIB) $(PNG_LIBS) \
	    $(EXR_LIBS) -lm -pthread

$(BUILD)/fuzz_exr: tests/fuzz/exr/fuzz_exr.c $(LIB)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(EXR_CFLAGS) -fsanitize=fuzzer -Isrc -o $@ $< $(LIB) \
	    $(PNG_LIBS) $(EXR_LIBS) $(STB_LIBS) -lm -pthread

$(BUILD)/fuzz_lua: tests/fuzz/lua/fuzz_lua.c $(LUA_OBJ) $(HELPER_OBJ) $(LIB)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(LUA_CFLAGS) -fsanitize=fuzzer -Isrc -o $@ $< \
	    $(LUA_OBJ) $(HELPER_OBJ) $(LIB) $(LUA_LIBS) $(PNG_LIBS) $(EXR_LIBS) -lm -pthread
endif

# The peers' files and images land in out/bench/ (tools/bench/), the report
# in out/bench/results.md.
# The naive build prices the robust code (tools/bench/robust.lua), the
# minimal one the full shading (tools/bench/parity.lua).
bench: all $(BUILD)/bin/lc-runstat
	@sh tools/install-deps.sh bench
	@$(MAKE) --no-print-directory $(BUILD)/bin/lc-raycast
	@$(MAKE) --no-print-directory NAIVE=1 build/naive/bin/lancer
	@$(MAKE) --no-print-directory MINIMAL=1 build/minimal/bin/lancer
	$(BIN) tools/bench/bench.lua $(if $(filter 1,$(QUICK)),quick)

# The Embree peer (tools/bench/embree.lua): bench only, never in lancer.
$(BUILD)/bin/lc-raycast: tools/bench/raycast.c $(LIB)
	@mkdir -p $(@D)
	$(CC) $(CFLAGS) -std=c11 -Isrc $(LDFLAGS) -o $@ $< $(LIB) -lembree3 $(PNG_LIBS) $(EXR_LIBS) -lm -pthread

$(BUILD)/bin/lc-runstat: tools/runstat.c
	@mkdir -p $(@D)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $<

clean:
	rm -rf $(BUILD) tests/out

-include $(CORE_OBJ:.o=.d) $(LUA_OBJ:.o=.d) $(HELPER_OBJ:.o=.d) $(HOST_OBJ:.o=.d) $(C_TESTS:=.d)
-include $(FUZZERS:%=$(BUILD)/fuzz_%.d)
