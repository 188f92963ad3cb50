#!/usr/bin/env bash
# Installs the Debian packages persp needs to build and test, only those missing.
# libassimp-dev imports models (OBJ, glTF, PLY, STL, FBX, ...); libstb-dev (stb_image) decodes GIF and HDR textures; libosmesa6-dev brings the Mesa peer (llvmpipe) that the tests compare images with;
# g++ compiles the public headers as C++ (tests/package); clang (for the
# libFuzzer harnesses) is installed with --optional. GNU parallel runs the
# sharded sweep of tests/cli/test_shard.sh; chromium (headless) loads the page
# of `persp report` in tests/cli/test_report.sh.
set -eu
# libsdl2-dev, libimgui-dev and fonts-dejavu-core build the window of `persp view`;
# xvfb runs it in a real X window in tests/cli/test_view_xvfb.sh.
required="cmake make gcc g++ pkg-config python3 libpng-dev libjpeg62-turbo-dev libjansson-dev libcmocka-dev libosmesa6-dev parallel chromium libsdl2-dev libimgui-dev fonts-dejavu-core libassimp-dev libstb-dev xvfb"
optional="clang"
# --aarch64: the cross build of `make test-aarch64` (cmake/aarch64-linux-gnu.cmake):
# the cross compiler, qemu-user to run its tests, and the arm64 builds of the
# libraries it links, from Debian's multiarch archive (the window of
# `persp view` and the Mesa peer are left out of that build).
aarch64="gcc-aarch64-linux-gnu g++-aarch64-linux-gnu qemu-user libc6-dev:arm64 libpng-dev:arm64 libjpeg62-turbo-dev:arm64 libjansson-dev:arm64 libcmocka-dev:arm64 libassimp-dev:arm64"
# --hw: the RTL flow of `make hw` (scripts/hw.sh, docs/HARDWARE.md): Verilator
# runs the testbenches, Yosys synthesizes, nextpnr-ice40 and the IceStorm
# chip database place and route for the iCE40 UP5K.
hw="verilator yosys nextpnr-ice40 fpga-icestorm"
# --slurm: a one-node Slurm for tests/cli/test_slurm.sh, which starts munged,
# slurmctld and slurmd itself in its temporary folder (docs/SWEEPS.md).
slurm="slurm-wlm munge"
want="$required"
[ "${1:-}" = "--hw" ] && want="$required $hw"
[ "${1:-}" = "--slurm" ] && want="$required $slurm"
[ "${1:-}" = "--optional" ] && want="$required $optional"
[ "${1:-}" = "--aarch64" ] && want="$required $aarch64"
missing=""
for p in $want; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
echo "deps: missing:$missing"
command -v apt-get >/dev/null ||
    { echo "deps: no apt-get: install these with your system's package manager" >&2; exit 1; }
sudo=""
if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null ||
        { echo "deps: not root and no sudo: run as root, or install sudo first (apt-get install sudo)" >&2; exit 1; }
    sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
if [ "${1:-}" = "--aarch64" ] && ! dpkg --print-foreign-architectures | grep -qx arm64; then
    $sudo dpkg --add-architecture arm64
fi
# A mirror caught mid-sync fails one architecture's index ("File has
# unexpected size"): the install below then says whether the lists that did
# arrive are enough.
echo "deps: apt-get update"
$sudo apt-get update -qq || echo "deps: apt-get update reported errors; installing from the lists there are"
# What apt will install with their dependencies (on a minimal Debian 12
# 344 packages, two to four minutes); then a line every few seconds while
# apt works. apt-get downloads everything first, then dpkg unpacks and sets
# up the packages in batches: on a minimal Debian the longest stretch
# without a package set up is the unpacking of about 180 of them (over a
# minute), so progress counts the downloads and unpacks as well.
# shellcheck disable=SC2086
total=$(apt-get install -s --no-install-recommends $missing 2>/dev/null | grep -c '^Inst ' || true)
echo "deps: installing $total packages (the ones above and what they need); progress every few seconds"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# shellcheck disable=SC2086
if ! $sudo apt-get install -y --no-install-recommends $missing >"$log" 2>&1; then
    tail -20 "$log" >&2
    echo "deps: apt-get install failed (above)" >&2
    exit 1
fi &
pid=$!
# "Get:N URL SUITE/COMPONENT ARCH PACKAGE ..." from apt, "Unpacking PACKAGE
# (VERSION) ..." and "Setting up PACKAGE (VERSION) ..." from dpkg.
progress() {
    awk -v total="$total" '
        /^Get:[0-9]/     { got++;  what = "downloading " $5 }
        /^Unpacking /    { unp++;  what = "unpacking " $2 }
        /^Setting up /   { set++;  what = "setting up " $3 }
        END {
            if (what == "") { print "waiting for apt"; exit }
            if (unp == 0 && set == 0) printf "[%d/%d downloaded] %s\n", got, total, what
            else printf "[%d/%d unpacked, %d/%d set up] %s\n", unp, total, set, total, what
        }' "$log"
}
# A line at most every 5 s when something moved, and one every 30 s when
# nothing did: one package can take a while (chromium's unpacking, a
# trigger), and a quiet terminal looks like a hang.
last=""
said=$SECONDS
while kill -0 "$pid" 2>/dev/null; do
    sleep 1
    now=$(progress)
    if [ "$now" != "$last" ] && [ $((SECONDS - said)) -ge 5 ]; then
        echo "deps: $now"
        last=$now
        said=$SECONDS
    elif [ "$now" = "$last" ] && [ $((SECONDS - said)) -ge 30 ]; then
        echo "deps: still working: $now"
        said=$SECONDS
    fi
done
wait "$pid"
echo "deps: done"
