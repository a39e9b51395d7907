#!/bin/sh
# run.sh smoke DIR: a short seeded run of each fuzzer built in DIR (make
#   fuzz-build), from its committed corpus, then each of its regression
#   inputs once; reports each as the Lua tests do (ok / FAIL / SKIP lines,
#   then "N passed, M failed"). Deterministic: -seed=1 and a fixed -runs.
# run.sh long DIR SECONDS [HARNESS...]: fuzzes each harness (default all)
#   for SECONDS (FUZZ_RUNS=N also stops after N executions), growing the
#   corpus DIR/corpus/HARNESS, going on past crashes (libFuzzer's fork
#   mode); crash inputs land in DIR/crashes/HARNESS/, grouped by their
#   sanitizer summary at the end, and the log in DIR/logs/HARNESS.log.
#   Exits 1 when a harness crashed.
# run.sh sig FILE: the crash signature of a sanitizer log (see below).
#
# Regressions: tests/fuzz/HARNESS/regressions/ holds every input that once
# crashed a harness; each must run clean. An input listed in that folder's
# PENDING file ("file: why", one a line) is a crash found and not fixed
# yet: it must still crash, and is reported as skipped; once it runs clean
# the test fails, saying to take it off the list. A smoke run that stops
# on a crash with a pending input's signature is that known bug: skipped,
# not failed; any other crash fails.
set -u
mode=${1:?usage: run.sh smoke DIR | long DIR SECONDS [HARNESS...] | sig FILE}
dir=${2:-build/fuzz}
here=tests/fuzz
harnesses="obj png lua exr hdr mtl"
# UBSan's reports stop the harness (-fno-sanitize-recover) with a stack.
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"

# A crash's signature: the sanitizer's kind of error and the function it
# names ("heap-use-after-free in lc_mesh_face_count"), else the first of
# lancer's functions on the stack (UBSan names none; a leak names malloc).
sig() {
    awk '
        /^SUMMARY: / && !s { s = $0 }
        /^    #[0-9]+ .* in [A-Za-z_]+ .*\/(src|tests\/fuzz)\// && !f {
            for (i = 1; i <= NF; i++) if ($i == "in") { f = $(i + 1); break }
        }
        END {
            if (!s) { print "no sanitizer summary"; exit }
            sub(/^SUMMARY: [A-Za-z]+: /, "", s)
            if (s ~ /leaked in/) { print "leak from " f; exit }
            n = split(s, w, " ")
            if (w[n - 1] == "in" && n > 2) print w[1] " in " w[n]
            else if (f) print w[1] " in " f
            else print s
        }' "$1"
}

# Executions of the smoke run, about two seconds each on one core.
smoke_runs() {
    case $1 in
        obj) echo 10000 ;;
        png) echo 20000 ;;
        lua) echo 1000 ;;
        exr) echo 10000 ;;
        hdr) echo 20000 ;;
        mtl) echo 10000 ;;
    esac
}

# libFuzzer's options for every run of harness $1. No legitimate path takes
# 512 MB at once (the harnesses cap the core's allocations at 256 MB and
# less): a larger malloc is a finding, reported at once, never performed.
# The Lua harness's inputs are programs: a longer input is more calls, and
# each call is capped.
opts() {
    o="-dict=$here/$1/$1.dict -timeout=20 -rss_limit_mb=2048 -malloc_limit_mb=512"
    case $1 in
        lua) o="$o -max_len=2048" ;;
        *)   o="$o -max_len=4096" ;;
    esac
    echo "$o"
}

if [ "$mode" = sig ]; then
    sig "$2"
    exit 0
fi

if [ "$mode" = long ]; then
    seconds=${3:-60}
    shift 3 2>/dev/null || shift $#
    [ $# -gt 0 ] && harnesses="$*"
    if [ "$(cat "$dir/toolchain" 2>/dev/null)" != ok ]; then
        echo "fuzz: cannot fuzz: $(cat "$dir/toolchain" 2>/dev/null || echo "no $dir")" >&2
        exit 1
    fi
    status=0
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    for h in $harnesses; do
        mkdir -p "$dir/corpus/$h" "$dir/crashes/$h" "$dir/logs"
        log=$dir/logs/$h.log
        before=$(ls "$dir/crashes/$h" | wc -l)
        echo "== fuzz_$h: $seconds s${FUZZ_RUNS:+ or $FUZZ_RUNS runs}, corpus $dir/corpus/$h, log $log"
        # -fork=1: the fuzzing runs in a child that is restarted after a
        # crash, so one known bug does not end the campaign.
        # shellcheck disable=SC2046
        "$dir/fuzz_$h" $(opts "$h") -fork=1 -ignore_crashes=1 -ignore_timeouts=1 \
            -ignore_ooms=1 -max_total_time="$seconds" ${FUZZ_RUNS:+-runs=$FUZZ_RUNS} \
            -artifact_prefix="$dir/crashes/$h/" \
            "$dir/corpus/$h" "$here/$h/corpus" >"$log" 2>&1
        grep -E '^#[0-9]+: cov:' "$log" | tail -1
        after=$(ls "$dir/crashes/$h" | wc -l)
        if [ "$after" -gt "$before" ]; then
            status=1
            echo "fuzz_$h: $((after - before)) new crash inputs in $dir/crashes/$h/; by signature:"
            for c in "$dir/crashes/$h"/*; do
                # shellcheck disable=SC2046
                "$dir/fuzz_$h" $(opts "$h") "$c" >"$tmp/log" 2>&1
                echo "$(sig "$tmp/log")|$c"
            done | sort | awk -F'|' '
                $1 != last { if (last != "") print "  " n "x " last " (e.g. " eg ")"
                             last = $1; n = 0; eg = $2 }
                { n++ }
                END { if (last != "") print "  " n "x " last " (e.g. " eg ")" }'
        fi
    done
    exit $status
fi

[ "$mode" = smoke ] || { echo "run.sh: unknown mode '$mode'" >&2; exit 2; }
passed=0 failed=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
: >"$tmp/skips"

ok()   { echo "ok   $1"; passed=$((passed + 1)); }
fail() { echo "FAIL $1"; sed 's/^/  /' "$2" | tail -60; failed=$((failed + 1)); }
skip() { echo "SKIP $1 ($2)"; echo "$1 ($2)" >>"$tmp/skips"; }

toolchain=$(cat "$dir/toolchain" 2>/dev/null || echo "no $dir/toolchain: make fuzz-build not run")
for h in $harnesses; do
    bin=$dir/fuzz_$h
    name="tests/fuzz: fuzz_$h"
    if [ "$toolchain" != ok ]; then
        skip "$name" "$toolchain"
        continue
    fi
    # The regressions first: the pending ones' signatures name known bugs.
    regs=$here/$h/regressions
    clean="" count=0
    : >"$tmp/known"
    for r in "$regs"/*; do
        [ -f "$r" ] || continue
        base=$(basename "$r")
        case $base in PENDING | *.lua) continue ;; esac   # the list; plain-Lua copies
        why=$(sed -n "s/^$base: //p" "$regs/PENDING" 2>/dev/null | head -1)
        if [ -n "$why" ]; then
            # shellcheck disable=SC2046
            if "$bin" $(opts "$h") "$r" >"$tmp/log" 2>&1; then
                echo "  $regs/$base runs clean now: remove its line from $regs/PENDING" \
                    >>"$tmp/log"
                fail "$name: pending regression $base" "$tmp/log"
            else
                echo "$(sig "$tmp/log")|$base: $why" >>"$tmp/known"
                skip "$name: regression $base" "pending fix: $(sig "$tmp/log"): $why"
            fi
        else
            clean="$clean $r" count=$((count + 1))
        fi
    done
    if [ "$count" -gt 0 ]; then
        # shellcheck disable=SC2046,SC2086
        if "$bin" $(opts "$h") $clean >"$tmp/log" 2>&1; then
            ok "$name: $count regression inputs run clean"
        else
            fail "$name: regression inputs (one of$clean)" "$tmp/log"
        fi
    fi
    n=$(smoke_runs "$h")
    mkdir -p "$tmp/$h/new" "$tmp/$h/crash"
    # New inputs go to the first folder (a scratch one), never to the corpus.
    # shellcheck disable=SC2046
    if "$bin" $(opts "$h") -seed=1 -runs="$n" -artifact_prefix="$tmp/$h/crash/" \
            "$tmp/$h/new" "$here/$h/corpus" >"$tmp/log" 2>&1; then
        ok "$name: $n seeded runs from its corpus ($(grep -o 'cov: [0-9]*' "$tmp/log" |
            tail -1))"
        continue
    fi
    s=$(sig "$tmp/log")
    for c in "$tmp/$h/crash"/*; do
        [ -f "$c" ] && mkdir -p "$dir/crashes/$h" && cp "$c" "$dir/crashes/$h/" &&
            echo "  crash input kept as $dir/crashes/$h/$(basename "$c")" >>"$tmp/log"
    done
    known=$(awk -F'|' -v s="$s" '$1 == s { print $2; exit }' "$tmp/known")
    if [ -n "$known" ]; then
        skip "$name: $n seeded runs from its corpus" "stopped on a known crash, $s, as $known"
    else
        fail "$name: $n seeded runs from its corpus: $s" "$tmp/log"
    fi
done

s=$(grep -c . "$tmp/skips")
if [ "$s" -gt 0 ]; then
    echo "$s SKIPPED, not counted as passed:"
    sed 's/^/  /' "$tmp/skips"
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
