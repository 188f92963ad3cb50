#!/usr/bin/env bash
# The install tree and the three ways a project consumes persp:
#   1. pkg-config (shared, and the static archives with --static),
#   2. find_package(persp CONFIG) against the install tree,
#   3. add_subdirectory() of the source tree from a parent project.
# Every example is built each way and run. Also checks the exported symbols
# of the shared libraries and that the public headers compile as strict C11
# and as C++17.
#
#   tests/package/test_install.sh SOURCE_DIR BUILD_DIR
#
# BUILD_DIR must be built; it is installed into a temporary prefix.
set -eEu -o pipefail

src=$(cd "${1:?usage: test_install.sh SOURCE_DIR BUILD_DIR}" && pwd)
build=$(cd "${2:?usage: test_install.sh SOURCE_DIR BUILD_DIR}" && pwd)

tmp=$(mktemp -d "${TMPDIR:-/tmp}/persp-package.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
trap 'echo "FAIL: line $LINENO: $BASH_COMMAND" >&2' ERR

fail() {
    echo "FAIL: $*" >&2
    exit 1
}
step() { echo "== $*"; }

cc=${CC:-cc}
cxx=${CXX:-c++}
jobs=2
# Consumers' warnings: the examples are meant to be copied into such builds.
strict_c=(-std=c11 -Wall -Wextra -Wpedantic -Werror)

version=$(sed -n 's/^#define PERSP_VERSION_STRING "\(.*\)"$/\1/p' "$src/include/persp.h")
[ -n "$version" ] || fail "no PERSP_VERSION_STRING in include/persp.h"
soversion=${version%.*}

libdir_rel=$(sed -n 's/^CMAKE_INSTALL_LIBDIR:[A-Z]*=//p' "$build/CMakeCache.txt")
prefix=$tmp/prefix
libdir=$prefix/${libdir_rel:-lib}

step "install into $prefix"
cmake --install "$build" --prefix "$prefix" >"$tmp/install.log" ||
    { cat "$tmp/install.log"; fail "cmake --install $build"; }

step "installed files"
expect_file() { [ -f "$1" ] || fail "not installed: ${1#"$prefix"/}"; }
expect_link() {
    [ -L "$1" ] || fail "not a symbolic link: ${1#"$prefix"/}"
    [ "$(readlink "$1")" = "$2" ] || fail "${1#"$prefix"/} -> $(readlink "$1"), expected $2"
}
for lib in persp persp_analysis; do
    expect_file "$libdir/lib$lib.so.$version"
    expect_link "$libdir/lib$lib.so.$soversion" "lib$lib.so.$version"
    expect_link "$libdir/lib$lib.so" "lib$lib.so.$soversion"
    expect_file "$libdir/lib$lib.a"
    soname=$(readelf -d "$libdir/lib$lib.so.$version" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
    [ "$soname" = "lib$lib.so.$soversion" ] || fail "lib$lib.so: SONAME '$soname', expected lib$lib.so.$soversion"
done
expect_file "$prefix/include/persp.h"
expect_file "$prefix/include/persp_analysis.h"
[ -x "$prefix/bin/persp" ] || fail "not installed: bin/persp"
expect_file "$libdir/pkgconfig/persp.pc"
expect_file "$libdir/pkgconfig/persp-analysis.pc"
for f in perspConfig.cmake perspConfigVersion.cmake perspTargets.cmake; do
    expect_file "$libdir/cmake/persp/$f"
done

step "models through the installed persp-import"
[ -x "$prefix/libexec/persp/persp-import" ] || fail "not installed: libexec/persp/persp-import"
"$prefix/bin/persp" render "$src/tests/data/models/triangle.dae" --size 64x48 -o "$tmp/model.png" \
    >"$tmp/model.log" 2>&1 || { cat "$tmp/model.log"; fail "bin/persp could not import a model"; }

step "bin/persp --version"
out=$("$prefix/bin/persp" --version)
[ "$out" = "persp $version" ] || fail "persp --version printed '$out', expected 'persp $version'"

# Functions declared in an installed header, comments removed first.
declared() {
    "$cc" -fpreprocessed -dD -E -P "$1" 2>/dev/null |
        grep -oE '\bpersp_[A-Za-z0-9_]+[[:space:]]*\(' | sed 's/[[:space:]]*($//' | sort -u
}
exported() { nm -D --defined-only "$1" | awk '{ print $NF }' | sort -u; }

step "exported symbols"
declared "$prefix/include/persp.h" >"$tmp/core.declared"
declared "$prefix/include/persp_analysis.h" >"$tmp/analysis.declared"
exported "$libdir/libpersp.so" >"$tmp/core.exported"
exported "$libdir/libpersp_analysis.so" >"$tmp/analysis.exported"
check_exports() { # LIBRARY HEADER DECLARED EXPORTED
    local extra missing
    extra=$(comm -13 "$3" "$4")
    missing=$(comm -23 "$3" "$4")
    [ -z "$extra" ] || fail "$1 exports what $2 does not declare:" $extra
    [ -z "$missing" ] || fail "$1 does not export what $2 declares:" $missing
}
# libpersp.so also exports the persp__ internals libpersp_analysis.so calls
# (src/core/shared.h), and no other: the analysis library links against
# libpersp.so rather than carrying a copy of the core.
nm -D --undefined-only "$libdir/libpersp_analysis.so" | awk '{ print $NF }' | sort -u >"$tmp/analysis.imported"
internal=$(grep '^persp__' "$tmp/core.exported" | comm -23 - "$tmp/analysis.imported")
[ -z "$internal" ] || fail "libpersp.so exports internals libpersp_analysis.so does not call:" $internal
grep -v '^persp__' "$tmp/core.exported" >"$tmp/core.public"
readelf -d "$libdir/libpersp_analysis.so" | grep -q "(NEEDED).*\[libpersp\.so\.$soversion\]" ||
    fail "libpersp_analysis.so does not depend on libpersp.so.$soversion"
check_exports libpersp.so persp.h "$tmp/core.declared" "$tmp/core.public"
check_exports libpersp_analysis.so persp_analysis.h "$tmp/analysis.declared" "$tmp/analysis.exported"

step "public headers as C11 and C++17"
mkdir -p "$tmp/headers"
for h in persp.h persp_analysis.h; do
    # Each header first in its translation unit: it must include what it needs.
    printf '#include <%s>\n#include <persp.h>\n#include <persp_analysis.h>\nint main(void) { return 0; }\n' "$h" \
        >"$tmp/headers/$h.c"
    "$cc" "${strict_c[@]}" -I"$prefix/include" -fsyntax-only "$tmp/headers/$h.c"
    cp "$tmp/headers/$h.c" "$tmp/headers/$h.cpp"
    "$cxx" -std=c++17 -Wall -Wextra -Wpedantic -Werror -I"$prefix/include" -fsyntax-only "$tmp/headers/$h.cpp"
done
# extern "C": a C++ program links against the C libraries.
cat >"$tmp/headers/link.cpp" <<'EOF'
#include <persp.h>
#include <persp_analysis.h>
#include <cstdio>
#include <cstring>
int main()
{
    persp_context *ctx = nullptr;
    if (persp_context_create(nullptr, &ctx) != PERSP_OK) return 1;
    const bool ok = std::strcmp(persp_version(), PERSP_VERSION_STRING) == 0 &&
                    persp_accuracy_case_count() > 0;
    persp_context_destroy(ctx);
    std::printf("C++: persp %s\n", persp_version());
    return ok ? 0 : 1;
}
EOF
"$cxx" -std=c++17 -Wall -Wextra -Werror -I"$prefix/include" "$tmp/headers/link.cpp" \
    -L"$libdir" -lpersp_analysis -lpersp -o "$tmp/headers/link"
LD_LIBRARY_PATH=$libdir "$tmp/headers/link"

examples=()
for f in "$src"/examples/*.c; do examples+=("$(basename "$f" .c)"); done
[ ${#examples[@]} -gt 0 ] || fail "no examples in $src/examples"

# Runs every example built into DIR (as DIR/NAME) in a scratch directory;
# with "static", also checks that none loads a persp shared library.
run_examples() { # LABEL DIR [static]
    local label=$1 dir=$2 linkage=${3:-shared} name work rc
    for name in "${examples[@]}"; do
        [ -x "$dir/$name" ] || fail "$label: $name was not built"
        if [ "$linkage" = static ]; then
            case $(readelf -d "$dir/$name") in
            *"Shared library: [libpersp"*) fail "$label: $name needs a persp shared library" ;;
            esac
        fi
        work=$tmp/run/$label/$name
        mkdir -p "$work"
        rc=0
        (cd "$work" && "$dir/$name" >"$work/stdout" 2>&1) || rc=$?
        if [ $rc -ne 0 ]; then
            cat "$work/stdout"
            fail "$label: $name exited with status $rc"
        fi
        echo "   $label: $(head -n 1 "$work/stdout")"
    done
}

# The pkg-config module an example needs.
module_of() { if grep -q '<persp_analysis.h>' "$src/examples/$1.c"; then echo persp-analysis; else echo persp; fi; }

step "examples with pkg-config"
export PKG_CONFIG_PATH=$libdir/pkgconfig
pkg-config --exact-version="$version" persp || fail "pkg-config: persp is not version $version"
for linkage in shared static; do
    out=$tmp/pkgconfig-$linkage
    mkdir -p "$out"
    for name in "${examples[@]}"; do
        if [ "$linkage" = shared ]; then
            # shellcheck disable=SC2046
            "$cc" "${strict_c[@]}" "$src/examples/$name.c" $(pkg-config --cflags --libs "$(module_of "$name")") \
                -o "$out/$name"
        else
            # --static lists what the archives need; -l:libNAME.a makes the
            # linker take the archive although the .so sits next to it.
            # shellcheck disable=SC2046
            "$cc" "${strict_c[@]}" "$src/examples/$name.c" \
                $(pkg-config --static --cflags --libs "$(module_of "$name")" |
                    sed -E 's/(^| )-l(persp|persp_analysis)( |$)/\1-l:lib\2.a\3/g; s/(^| )-l(persp|persp_analysis)( |$)/\1-l:lib\2.a\3/g') \
                -o "$out/$name"
        fi
    done
    if [ "$linkage" = shared ]; then
        LD_LIBRARY_PATH=$libdir run_examples "pkg-config" "$out"
    else
        run_examples "pkg-config --static" "$out" static
    fi
done
unset PKG_CONFIG_PATH

cmake_build() { # LABEL SOURCE BINARY [cmake options...]
    local label=$1 source=$2 binary=$3
    shift 3
    cmake -S "$source" -B "$binary" -DCMAKE_BUILD_TYPE=Release "$@" >"$binary.log" 2>&1 ||
        { cat "$binary.log"; fail "$label: cmake configure"; }
    cmake --build "$binary" -j "$jobs" >>"$binary.log" 2>&1 ||
        { cat "$binary.log"; fail "$label: cmake build"; }
}

step "examples with find_package(persp)"
# The shared builds run without LD_LIBRARY_PATH: CMake's build RPATH points
# at the imported libraries.
cmake_build "find_package" "$src/examples" "$tmp/find-package" -DCMAKE_PREFIX_PATH="$prefix"
run_examples "find_package" "$tmp/find-package"
# A program linking the installed libpersp.so finds persp-import from the
# library's own place (PREFIX/libexec/persp/), whatever the prefix.
"$tmp/find-package/render_scene" "$src/tests/data/models/triangle.dae" "$tmp/model-shared.png" \
    >"$tmp/model-shared.log" 2>&1 || { cat "$tmp/model-shared.log"; fail "find_package: render_scene could not import a model"; }
cmake_build "find_package static" "$src/examples" "$tmp/find-package-static" \
    -DCMAKE_PREFIX_PATH="$prefix" -DPERSP_EXAMPLES_STATIC=ON
run_examples "find_package static" "$tmp/find-package-static" static

step "find_package(persp VERSION): same minor only while 0.x"
major=${version%%.*}
minor=${soversion#*.}
find_version() { # REQUESTED -> prints persp_FOUND
    local dir=$tmp/find-version-$1
    mkdir -p "$dir"
    printf 'cmake_minimum_required(VERSION 3.16)\nproject(v LANGUAGES C)\nfind_package(persp %s CONFIG QUIET)\nmessage(STATUS "persp_FOUND=${persp_FOUND}")\n' \
        "$1" >"$dir/CMakeLists.txt"
    cmake -S "$dir" -B "$dir/build" -DCMAKE_PREFIX_PATH="$prefix" 2>&1 | sed -n 's/^-- persp_FOUND=//p'
}
[ "$(find_version "$major.$minor")" = 1 ] || fail "find_package(persp $major.$minor) does not accept $version"
[ "$(find_version "$major.$((minor + 1))")" = 0 ] ||
    fail "find_package(persp $major.$((minor + 1))) accepts $version"

step "examples with add_subdirectory(persp)"
mkdir -p "$tmp/parent"
cat >"$tmp/parent/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.16)
project(parent LANGUAGES C)
add_subdirectory("$src" persp)
add_subdirectory("$src/examples" examples)
EOF
cmake_build "add_subdirectory" "$tmp/parent" "$tmp/parent-build"
if grep -q '^CMOCKA_FOUND' "$tmp/parent-build/CMakeCache.txt"; then
    fail "add_subdirectory: persp looked for cmocka (tests are for persp's own build)"
fi
[ ! -e "$tmp/parent-build/persp/persp" ] || fail "add_subdirectory: persp built its CLI"
run_examples "add_subdirectory" "$tmp/parent-build/examples"
# Same tree, examples relinked against the static targets.
cmake_build "add_subdirectory static" "$tmp/parent" "$tmp/parent-build" -DPERSP_EXAMPLES_STATIC=ON
run_examples "add_subdirectory static" "$tmp/parent-build/examples" static

step "ok"
