#!/usr/bin/env bash
# Installs the Debian packages persp needs to build and test, only those missing.
# libassimp-dev imports models (OBJ, glTF, PLY, STL, FBX, ...); libosmesa6-dev brings the Mesa peer (llvmpipe) that the tests compare images with;
# g++ compiles the public headers as C++ (tests/package); clang (for the
# libFuzzer harnesses) is installed with --optional. GNU parallel runs the
# sharded sweep of tests/cli/test_shard.sh; chromium (headless) loads the page
# of `persp report` in tests/cli/test_report.sh.
set -eu
# libsdl2-dev, libimgui-dev and fonts-dejavu-core build the window of `persp view`;
# xvfb runs it in a real X window in tests/cli/test_view_xvfb.sh.
required="cmake make gcc g++ pkg-config python3 libpng-dev libjpeg62-turbo-dev libjansson-dev libcmocka-dev libosmesa6-dev parallel chromium libsdl2-dev libimgui-dev fonts-dejavu-core libassimp-dev xvfb"
optional="clang"
want="$required"
[ "${1:-}" = "--optional" ] && want="$required $optional"
missing=""
for p in $want; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
echo "deps: installing:$missing"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
# shellcheck disable=SC2086
$sudo apt-get install -y -qq --no-install-recommends $missing >/dev/null
