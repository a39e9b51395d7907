#!/bin/sh
# toolchain.sh CC DIR: can CC link a libFuzzer harness with ASan and UBSan?
# Writes the answer to DIR/toolchain ("ok", or why not, for the smoke run to
# report as a skip); exits 0 when it can. clang's libFuzzer and sanitizer
# runtimes come from Debian's libclang-rt-14-dev (tools/install-deps.sh).
set -u
cc=${1:-clang} dir=${2:-build/fuzz}
mkdir -p "$dir"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat >"$tmp/probe.c" <<'C'
#include <stddef.h>
#include <stdint.h>
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return size && data[0] == 'x';
}
C
if ! command -v "$cc" >/dev/null 2>&1; then
    why="no $cc on PATH (tools/install-deps.sh test installs clang)"
elif ! "$cc" -fsanitize=fuzzer,address,undefined -o "$tmp/probe" "$tmp/probe.c" \
        >"$tmp/log" 2>&1; then
    why="$cc -fsanitize=fuzzer,address,undefined does not link: $(head -1 "$tmp/log")"
else
    echo ok >"$dir/toolchain"
    exit 0
fi
echo "$why" >"$dir/toolchain"
echo "fuzz: skipped: $why" >&2
exit 1
