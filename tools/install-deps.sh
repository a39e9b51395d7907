#!/bin/sh
# install-deps.sh: install the Debian packages lancer needs, only those missing.
# Usage: tools/install-deps.sh [build|test|bench]
# Runs apt-get (through sudo when not root) only when something is missing,
# so a machine that already has everything is never touched.
set -eu

# libopenexr-dev: EXR output and input through OpenEXRCore, its C library (src/image/exr.c).
build_pkgs="gcc make pkg-config lua5.4 liblua5.4-dev libpng-dev libedit-dev libopenexr-dev"
# parallel: tests/lua/test_farm.lua splits an animation over GNU parallel workers.
# clang, libclang-rt-dev: the fuzzers' smoke run (tests/fuzz/); clang links
# libFuzzer and its sanitizers only with the compiler-rt libraries, which
# libclang-rt-dev (libclang-rt-14-dev on Debian 12) holds and clang merely
# recommends. About 55 MB; without them the smoke run is skipped.
# slurm-wlm, munge: tests/lua/test_slurm.lua runs the manual's Slurm recipes
# on a one-node cluster of its own (temporary conf, key and ports). 8 packages,
# 3.5 MB to fetch, 13 MB installed, 17 s to install on two cores. The system's
# slurmctld and slurmd stay off without an /etc/slurm/slurm.conf (munge's own
# service starts where systemd runs, on a local socket). Where the daemons
# cannot run (many containers), that test is skipped.
# ffmpeg is optional (about 300 packages): its tests are skipped without it.
test_pkgs="libcmocka-dev parallel clang libclang-rt-dev slurm-wlm munge"
# The bench's peers: POV-Ray and Tachyon render the same scenes; Embree 3
# traces the same rays (tools/bench/raycast.c; never linked into lancer).
bench_pkgs="povray tachyon libembree-dev"

case "${1:-build}" in
    build) want="$build_pkgs" ;;
    test)  want="$build_pkgs $test_pkgs" ;;
    bench) want="$build_pkgs $bench_pkgs" ;;
    *) echo "usage: $0 [build|test|bench]" >&2; exit 2 ;;
esac

missing=""
for p in $want; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
        missing="$missing $p"
    fi
done
[ -z "$missing" ] && exit 0

if ! command -v apt-get >/dev/null 2>&1; then
    echo "install-deps: missing packages:$missing (and no apt-get here; install them by hand)" >&2
    exit 1
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then sudo="sudo"; else
        echo "install-deps: need root or sudo to install:$missing" >&2; exit 1
    fi
fi
echo "install-deps: installing$missing" >&2
$sudo env DEBIAN_FRONTEND=noninteractive apt-get update -q >&2
$sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $missing >&2
