#!/bin/sh
# run.sh BUILD [FUZZ]: runs the C unit tests (cmocka) and the Lua tests
# against the tree BUILD, then, given FUZZ (the fuzzers' tree, build/fuzz),
# a short seeded run of each fuzzer (tests/fuzz/run.sh smoke); prints the
# skipped ones and one closing line "N passed, M failed" over all of them;
# exits 1 on failure.
#
# A sanitized BUILD (make SAN=1, build/san) runs the same tests under ASan,
# UBSan and LeakSanitizer, every report written to BUILD/reports/ rather
# than to a stderr some test may swallow: each report counts as a failure
# and is printed at the end. The Lua suite then runs in BUILD's lancer (it
# links the ASan runtime first, which the stock lua5.4 cannot load the
# sanitized module without), its host hook removed so the binding is met
# as from lua5.4; lua5.4 and cc on PATH preload or link the runtimes for
# the tests that call them. Then the fuzzers' regressions written as plain
# Lua run in that lancer: the bugs they found, until fixed, show here.
set -u
build=${1:-build}
fuzz=${2:-}
passed=0 failed=0 skipped=0
log=$(mktemp)
tmp=$(mktemp -d)
trap 'rm -rf "$log" "$tmp"' EXIT

lua_run="lua5.4"
san=0
if nm "$build/liblancer.a" 2>/dev/null | grep -q __asan_; then
    san=1
    reports=$(pwd)/$build/reports
    rm -rf "$reports" && mkdir -p "$reports"
    # halt_on_error: the first report ends the process (UBSan too: the build
    # has -fno-sanitize-recover=all). exitcode 86: no test mistakes a report
    # for an ordinary failure exit. verify_asan_link_order=0: stdbuf (the
    # docs' transcripts) preloads libstdbuf, which defines no allocator, ahead
    # of the runtime; ASan would refuse to start, not find anything more.
    export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:exitcode=86:verify_asan_link_order=0:log_path=$reports/asan"
    export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:exitcode=86:log_path=$reports/ubsan"
    mkdir "$tmp/bin"
    asan=$(cc -print-file-name=libasan.so) ubsan=$(cc -print-file-name=libubsan.so)
    cat >"$tmp/bin/lua5.4" <<EOF
#!/bin/sh
LD_PRELOAD="$asan $ubsan\${LD_PRELOAD:+ \$LD_PRELOAD}" exec $(command -v lua5.4) "\$@"
EOF
    cat >"$tmp/bin/cc" <<EOF
#!/bin/sh
exec $(command -v cc) -fsanitize=address,undefined -fno-sanitize-recover=all "\$@"
EOF
    chmod +x "$tmp/bin/lua5.4" "$tmp/bin/cc"
    export PATH="$tmp/bin:$PATH"
    lua_run="$build/bin/lancer -e lancer.set_host_hook(nil)"
    echo "== sanitizers: ASan + UBSan + LSan, reports to $build/reports/"
fi

for t in "$build"/tests/test_*; do
    [ -x "$t" ] || continue
    echo "== $t"
    "$t" >"$log" 2>&1
    rc=$?
    cat "$log"
    # cmocka writes these to stderr, interleaved with stdout: match anywhere.
    p=$(grep -o '\[  PASSED  \] [0-9]* test' "$log" | tail -1 | tr -dc 0-9)
    f=$(grep -o '\[  FAILED  \] [0-9]* test' "$log" | tail -1 | tr -dc 0-9)
    p=${p:-0} f=${f:-0}
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi   # crashed before reporting
    passed=$((passed + p)) failed=$((failed + f))
done

# Adds the counts of the last "N passed, M failed" line of $log, and its
# skips ("K SKIPPED, not counted as passed:" and the lines after it).
tally() {
    line=$(grep -E '^[0-9]+ passed, [0-9]+ failed$' "$log" | tail -1)
    p=$(echo "$line" | sed -n 's/^\([0-9]*\) passed.*/\1/p')
    f=$(echo "$line" | sed -n 's/.* \([0-9]*\) failed$/\1/p')
    s=$(sed -n 's/^\([0-9]*\) SKIPPED, not counted as passed:$/\1/p' "$log" | tail -1)
    p=${p:-0} f=${f:-0} s=${s:-0}
    if [ "$1" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
    passed=$((passed + p)) failed=$((failed + f)) skipped=$((skipped + s))
    sed -n '/^[0-9]* SKIPPED, not counted as passed:$/,/^[0-9]* passed, [0-9]* failed$/p' \
        "$log" | sed '1d;$d' >>"$tmp/skips"
}

echo "== Lua tests"
LUA_PATH="lua/?.lua;lua/?/init.lua;tests/lua/?.lua;;" LUA_CPATH="$build/?.so;;" \
LANCER_BIN="$build/bin/lancer" $lua_run tests/lua/all.lua >"$log" 2>&1
rc=$?
cat "$log"
tally $rc

# The fuzzers' finds, as the plain-Lua scripts beside their regression
# inputs (tests/fuzz/*/regressions/NAME.lua), each run by the sanitized
# lancer: one that raises a sanitizer report fails (the report is counted
# below); an ordinary Lua error is what a fixed binding gives, and passes.
if [ "$san" -eq 1 ]; then
    echo "== the fuzzers' regressions in plain Lua, under the sanitizers"
    mkdir "$tmp/work"
    for r in tests/fuzz/*/regressions/*.lua; do
        [ -f "$r" ] || continue
        ls "$reports" >"$tmp/before"
        (cd "$tmp/work" && "$OLDPWD/$build/bin/lancer" "$OLDPWD/$r") >"$log" 2>&1
        rc=$?
        new=$(ls "$reports" | comm -13 "$tmp/before" - | sed "s|^|$build/reports/|")
        if [ -n "$new" ]; then
            echo "FAIL $r: a sanitizer report, shown below:" $new
        elif [ "$rc" -gt 1 ]; then
            echo "FAIL $r: exit $rc"
            sed 's/^/  /' "$log"
            failed=$((failed + 1))
        else
            echo "ok   $r: no report (exit $rc)"
            passed=$((passed + 1))
        fi
    done
fi

if [ -n "$fuzz" ]; then
    echo "== fuzzers (smoke: seeded, a few seconds each)"
    sh tests/fuzz/run.sh smoke "$fuzz" >"$log" 2>&1
    rc=$?
    cat "$log"
    tally $rc
fi

if [ "$san" -eq 1 ]; then
    n=$(ls "$reports" | wc -l)
    echo "== sanitizer reports: $n"
    for r in "$reports"/*; do
        [ -f "$r" ] || continue
        echo "-- $build/reports/$(basename "$r")"
        cat "$r"
    done
    failed=$((failed + n))
fi

if [ "$skipped" -gt 0 ]; then
    echo "$skipped SKIPPED, not counted as passed:"
    cat "$tmp/skips"
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
