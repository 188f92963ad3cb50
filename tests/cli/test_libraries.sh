#!/usr/bin/env bash
# The shared libraries as built: libpersp_analysis.so links against
# libpersp.so instead of carrying a copy of the core (it defines none of
# libpersp.so's symbols and needs libpersp.so), libpersp.so exports no
# internal symbol beyond those the analysis library calls, and neither
# holds mutable data of its own: every public function is reentrant
# (include/persp.h, "Threads"). The one process-wide object is the mutex
# of in-process model imports (src/model/model.c); the others listed are the
# C runtime's and libgcc's. (The persp binary in $1 is not used.)
set -u
. "$(dirname "$0")/lib.sh"

core=$PERSP_BINARY_DIR/libpersp.so
analysis=$PERSP_BINARY_DIR/libpersp_analysis.so
# The build's own binutils (a cross build's aarch64-linux-gnu-nm), from CMake.
nm=${PERSP_TEST_NM:-nm} readelf=${PERSP_TEST_READELF:-readelf} objdump=${PERSP_TEST_OBJDUMP:-objdump}
for tool in "$nm" "$readelf" "$objdump"; do
    command -v "$tool" >/dev/null || { echo "SKIP: no $tool (binutils)"; exit 0; }
done
[ -f "$core" ] && [ -f "$analysis" ] || { bad "shared libraries not built in $PERSP_BINARY_DIR"; exit 1; }

defined() { "$nm" -D --defined-only "$1" | awk '{ print $NF }' | sort -u; }
defined "$core" >"$tmp/core"
defined "$analysis" >"$tmp/analysis"
"$nm" -D --undefined-only "$analysis" | awk '{ print $NF }' | sort -u >"$tmp/analysis.undefined"

# One core: no symbol of libpersp.so defined again in the analysis library...
both=$(comm -12 "$tmp/core" "$tmp/analysis")
[ -z "$both" ] && ok || bad "libpersp_analysis.so defines core symbols:" $both
# ...which takes them from libpersp.so.
"$readelf" -d "$analysis" | grep -qE "\(NEEDED\).*\[libpersp\.so\." && ok ||
    bad "libpersp_analysis.so does not depend on libpersp.so: $("$readelf" -d "$analysis" | grep NEEDED)"
[ -n "$(grep '^persp_' "$tmp/analysis.undefined" | comm -12 - "$tmp/core")" ] && ok ||
    bad "libpersp_analysis.so imports no public function of libpersp.so"
# libpersp.so's internals (persp__) exported: only what the analysis library imports.
extra=$(grep '^persp__' "$tmp/core" | comm -23 - "$tmp/analysis.undefined")
[ -z "$extra" ] && ok || bad "libpersp.so exports internals the analysis library does not use:" $extra
[ "$(grep -c '^persp__' "$tmp/analysis.undefined")" -gt 0 ] && ok || bad "no persp__ import in libpersp_analysis.so"

# No mutable data: the objects in writable sections of each library
# (AddressSanitizer's one-definition-rule markers, __odr_asan.NAME, are its
# own, one per global; stb_image's stbi__ settings, which an unoptimised
# build keeps as data, are changed only by setters persp never calls).
allowed='^(import_lock|completed\.0|__TMC_END__|__dso_handle|__cpu_model|__cpu_features2|__aarch64_have_lse_atomics)$'
for lib in "$core" "$analysis"; do
    writable=$("$objdump" -t "$lib" | awk '$4 ~ /^\.(data|bss|tdata|tbss)$/ && $3 == "O" { print $NF }' |
        grep -vE "$allowed" | grep -v '^__odr_asan\.' | grep -v '^stbi__' | sort -u)
    [ -z "$writable" ] && ok || bad "$(basename "$lib") holds mutable data:" $writable
done

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
