#!/usr/bin/env bash
# Files, output and parsing (docs/RELIABILITY.md, "Files, output and
# parsing"): what a scene or model may read (--any-folder), messages that
# never show another file's content or raw control bytes, outputs that
# replace files safely (modes, links, read-only files, devices, signals),
# strict option values and method specs, folders given as files, output
# paths checked before the work, and write errors from every command.
set -u
persp="$1"
src="${PERSP_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"
. "$(dirname "$0")/lib.sh"

# expect_not CODE PATTERN -- command...: exit code, and PATTERN absent from the output
expect_not() {
    local code="$1" pattern="$2"; shift 3
    local out rc
    out=$("$@" 2>&1); rc=$?
    if [ "$rc" -ne "$code" ]; then bad "$* exited $rc, expected $code: $out"; return; fi
    if grep -qaE -- "$pattern" <<<"$out"; then bad "$* output has /$pattern/: $out"; return; fi
    ok
}

# ---------------------------------------------------------------- file access
s="$tmp/s"
mkdir -p "$s/sub/in"
cp "$src/scenes/textures/checker.png" "$s/outside.png"
cp "$src/scenes/textures/checker.png" "$s/sub/in/t.png"
ln -s .. "$s/sub/up"
scene() { # scene NAME TEXTURE: a plane textured with TEXTURE
    printf '{"materials": {"m": {"texture": "%s"}},\n "objects": [{"mesh": "plane", "material": "m"}]}\n' "$2" >"$s/sub/$1"
}
scene ok.json in/t.png
scene dotdot.json ../outside.png
scene abs.json "$s/outside.png"
scene link.json up/outside.png
scene passwd.json /etc/passwd
expect 0 "rendered" -- "$persp" render "$s/sub/ok.json" --size 16x16 -o "$tmp/a.png"
for f in dotdot abs link passwd; do
    expect 1 "$f.json:1:[0-9]+: materials.m.texture: '.*' is outside the folder the scene may read from" -- \
        "$persp" render "$s/sub/$f.json" --size 16x16 -o "$tmp/a.png"
done
expect 0 "rendered" -- "$persp" render "$s/sub/dotdot.json" --any-folder --size 16x16 -o "$tmp/a.png"
expect 0 "" -- "$persp" bench "$s/sub/link.json" --any-folder --size 16x16 --frames 1 --reps 1
expect 1 "is outside the folder" -- "$persp" bench "$s/sub/link.json" --size 16x16 --frames 1 --reps 1
expect 1 "is outside the folder" -- "$persp" accuracy --shading --scene "$s/sub/abs.json" --triangles 1
expect 2 "unknown option '--any-folder'" -- "$persp" merge --any-folder x.json

# A model: its material library and texture outside the folder are skipped
# with a warning naming the model and the line; nothing of the refused file
# is shown, with or without --any-folder.
m="$tmp/m"
mkdir -p "$m"
printf 'root:x:0:0:root:/root:/bin/bash\n' >"$tmp/secret.mtl"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib ../secret.mtl\nusemtl root\nf 1 2 3\n' >"$m/a.obj"
expect 0 "a.obj:4: cannot read '../secret.mtl' \(outside the folder the model may read from\)" -- \
    "$persp" render "$m/a.obj" --size 16x16 -o "$tmp/a.png"
expect_not 0 "root:x" -- "$persp" render "$m/a.obj" --any-folder --size 16x16 -o "$tmp/a.png"
printf 'newmtl x\nKd 1 1 1\nmap_Kd ../../etc/passwd\n' >"$m/b.mtl"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib b.mtl\nusemtl x\nf 1 2 3\n' >"$m/b.obj"
expect_not 0 "root:x" -- "$persp" render "$m/b.obj" --any-folder --size 16x16 -o "$tmp/a.png"
# a material library that is not one, next to the model, with a broken model
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib ../secret.mtl\nf 1 2 9\n' >"$m/c.obj"
expect_not 1 "root:x" -- "$persp" render "$m/c.obj" --any-folder --size 16x16 -o "$tmp/a.png"

# ------------------------------------------------------------- out of memory
# The decoders' own allocations fail (tests/cli/data/fail_alloc.c, preloaded;
# not with the sanitizers, whose runtime must come first). A cross build's
# tests name its compiler in PERSP_TEST_CC, so that the library preloaded
# into the emulated CLI is of the CLI's architecture.
cc_bin=${PERSP_TEST_CC:-$(command -v cc || command -v gcc || true)}
if [ -n "$cc_bin" ] && ! ldd "$persp" 2>/dev/null | grep -q libasan &&
    "$cc_bin" -shared -fPIC -O2 -o "$tmp/fail_alloc.so" "$src/tests/cli/data/fail_alloc.c" -ldl 2>/dev/null; then
    oom() { # oom LIBRARY PATTERN -- command...
        local lib="$1" pattern="$2"; shift 3
        expect 1 "$pattern" -- env PERSP_FAIL_ALLOC_IN="$lib" LD_PRELOAD="$tmp/fail_alloc.so" "$@"
    }
    oom libjpeg "checker.jpg: out of memory decoding the JPEG \(out of memory\)" -- \
        "$persp" render cube --size 8x8 --texture "$src/tests/cli/data/checker.jpg" -o "$tmp/a.png"
    oom libpng "checker.png: out of memory decoding the PNG \(out of memory\)" -- \
        "$persp" render cube --size 8x8 --texture "$src/scenes/textures/checker.png" -o "$tmp/a.jpg"
    oom libpng "a.png: out of memory encoding the PNG \(out of memory\)" -- \
        "$persp" render cube --size 8x8 -o "$tmp/a.png"
    oom libjpeg "a.jpg: out of memory encoding the JPEG \(out of memory\)" -- \
        "$persp" render cube --size 8x8 -o "$tmp/a.jpg"
    oom libjansson "spheres.json: out of memory parsing the JSON \(out of memory\)" -- \
        "$persp" render "$src/scenes/spheres.json" --size 8x8 -o "$tmp/a.png"
else
    echo "out-of-memory checks skipped (no C compiler, or a sanitizer build)"
fi

# ------------------------------------------------------------------ messages
printf '{"objects": [{"mesh": "plane", "material": "\\u001b]0;x\\u0007%s"}]}' \
    "$(head -c 300 /dev/zero | tr '\0' 'z')" >"$tmp/esc.json"
out=$("$persp" render "$tmp/esc.json" -o "$tmp/a.png" 2>&1)
if LC_ALL=C grep -q $'[\x01-\x08\x0b-\x1f]' <<<"$out"; then bad "control byte in: $out"
elif ! grep -q "no material named '.x1b\]0;x.x07zz*\.\.\.'" <<<"$out" || [ "${#out}" -gt 300 ]; then bad "escape/cap: $out"
else ok; fi
printf '{"render": {"method": "\\u001b[2J"}, "objects": [{"mesh": "plane"}]}' >"$tmp/esc2.json"
expect 1 "bad parameters '.x1b\[2J'" -- "$persp" render "$tmp/esc2.json" -o "$tmp/a.png"

# -------------------------------------------------------------------- output
o="$tmp/o"
mkdir -p "$o"
printf 'old' >"$o/m.png"; chmod 640 "$o/m.png"
expect 0 "" -- "$persp" render cube --size 8x8 -q -o "$o/m.png"
[ "$(stat -c %a "$o/m.png")" = 640 ] && [ "$(stat -c %s "$o/m.png")" -gt 3 ] && ok || bad "mode not kept: $(stat -c '%a %s' "$o/m.png")"
ln -s m.png "$o/l.png"
expect 0 "" -- "$persp" render floor --size 8x8 -q -o "$o/l.png"
[ -L "$o/l.png" ] && cmp -s "$o/l.png" "$o/m.png" && ok || bad "link replaced or target not written"
printf 'keep' >"$o/ro.png"; chmod 444 "$o/ro.png"
expect 1 "-o '.*ro.png' is read-only" -- "$persp" render cube --size 8x8 -q -o "$o/ro.png"
[ "$(cat "$o/ro.png")" = keep ] && ok || bad "read-only file changed"
printf 'keep' >"$o/ro.json"; chmod 444 "$o/ro.json"
expect 1 "ro.json' is read-only" -- "$persp" accuracy --case paper-quad --method affine --triangles 1 -o "$o/ro.json"
# Hard links: the rename gives the path a new file; the other name keeps
# the old content (documented choice: atomic replacement first).
printf 'old' >"$o/h1.png"; ln "$o/h1.png" "$o/h2.png"
expect 0 "" -- "$persp" render cube --size 8x8 -q -o "$o/h1.png"
[ "$(cat "$o/h2.png")" = old ] && [ "$(stat -c %s "$o/h1.png")" -gt 3 ] && ok || bad "hard link behaviour changed"
expect 0 "" -- "$persp" render cube --size 8x8 -q -o /dev/null
expect 1 "/dev/full: write failed" -- "$persp" render cube --size 8x8 -q -o /dev/full
expect 1 "/dev/full" -- "$persp" render cube --size 8x8 -q --format jpeg -o /dev/full
"$persp" render cube --size 8x8 -q -o - >"$o/stdout.png" && [ "$(head -c 4 "$o/stdout.png" | od -An -c | tr -d ' ')" = '211PNG' ] && ok || bad "-o - wrote no PNG"
[ -z "$(ls "$o" | grep tmp)" ] && ok || bad "temporary files left: $(ls "$o")"

# A signal during the write removes the temporary file: a report is
# written to its temporary file while the command computes, an image while
# it is encoded (a 3072x3072 PNG: about a third of a second, so that the
# signal, sent as soon as the file is seen, lands before the rename even on
# a loaded machine).
# On a machine loaded enough to keep this shell from running for the third
# of a second the write takes, the command can finish before the signal
# arrives (exit 0, the file complete and in place): that try says nothing
# and is made again, up to three times; a temporary file left, or the file
# in place after a signal that did arrive, fails at once.
sig_case() { # sig_case SIGNAL FILE -- command...
    local sig="$1" file="$2"; shift 3
    local try rc pid seen
    for try in 1 2 3; do
        "$@" & pid=$!
        # Seen once is enough: persp re-creates the file mkstemp made, so a
        # second look can fall in the moment it is absent.
        seen=
        for _ in $(seq 1 3000); do compgen -G "$file.tmp-*" >/dev/null && { seen=1; break; }; sleep 0.01; done
        if [ -z "$seen" ]; then wait "$pid"; bad "$sig: no temporary file seen"; return; fi
        kill -"$sig" "$pid" 2>/dev/null; wait "$pid"; rc=$?
        if [ "$rc" -eq 0 ] && [ -s "$file" ] && ! compgen -G "$file.tmp-*" >/dev/null; then
            echo "$sig: the command finished before the signal (try $try)"; rm -f "$file"; continue
        fi
        if compgen -G "$file*" >/dev/null; then bad "$sig: left $(ls "$file"*)"; return; fi
        [ "$rc" -ge 128 ] && ok || bad "$sig: exit $rc"
        return
    done
    bad "$sig: the command finished before the signal three times"
}
sig_case INT "$o/acc.json" -- "$persp" accuracy --case paper-quad,random-triangles --triangles 500 -o "$o/acc.json"
sig_case TERM "$o/big.png" -- "$persp" render corridor --size 3072x3072 -q -o "$o/big.png"

# ---------------------------------------------------- output paths, early
# "At once": within what starting persp takes (measured, so that an emulated
# or loaded machine is held to its own pace) plus half a second; the work
# refused takes seconds natively and minutes emulated.
t0=$(date +%s%N)
"$persp" render --help >/dev/null 2>&1
start_ms=$(( ($(date +%s%N) - t0) / 1000000 ))
for args in "render corridor --size 8192x8192 -o /nonexistent/dir/x.png" \
            "accuracy --shading --svg /nonexistent/x.svg" \
            "accuracy --case paper-quad -o /nonexistent/x.json" \
            "bench --size 8x8 -o /nonexistent/x.json"; do
    t0=$(date +%s%N)
    # shellcheck disable=SC2086
    expect 1 "nonexistent" -- "$persp" $args
    took=$(( ($(date +%s%N) - t0) / 1000000 ))
    [ "$took" -lt $((3 * start_ms + 500)) ] && ok || bad "$args: not refused at once (${took} ms; starting persp: ${start_ms} ms)"
done
expect 1 "render: -o '$o' is a directory" -- "$persp" render cube --size 8x8 --format png -o "$o"
expect 2 "cannot tell the image format of '.*x.gif'" -- "$persp" render cube -o "$o/x.gif"

# ------------------------------------------------------- folders as files
expect 1 "^persp: /tmp: is a directory, not a file" -- "$persp" render /tmp
expect 1 ": is a directory" -- "$persp" render cube --texture "$o" -o "$tmp/a.png"
mkdir -p "$s/sub/dir.png"
scene dir.json dir.png
expect 1 "dir.png: is a directory" -- "$persp" render "$s/sub/dir.json" -o "$tmp/a.png"
mkdir -p "$tmp/d.obj"
expect 1 "d.obj: is a directory, not a file" -- "$persp" render "$tmp/d.obj" -o "$tmp/a.png"

# ---------------------------------------------------------- strict parsing
expect 2 "bad --lod-bias '0x10' \(expected -16..16\)" -- "$persp" render --lod-bias 0x10 -o "$tmp/a.png"
expect 2 "bad --lod-bias '\+1'" -- "$persp" render --lod-bias +1 -o "$tmp/a.png"
expect 2 "bad --lod-bias 'inf'" -- "$persp" render --lod-bias inf -o "$tmp/a.png"
expect 2 "bad --threads ' 2'" -- "$persp" render --threads " 2" -o "$tmp/a.png"
expect 2 "bad --size ' 10x10'" -- "$persp" render --size " 10x10" -o "$tmp/a.png"
expect 2 "bad --size '10x\+10'" -- "$persp" render --size "10x+10" -o "$tmp/a.png"
expect 2 "bad --size '0x10x10'" -- "$persp" render --size "0x10x10" -o "$tmp/a.png"
expect 2 "bad --lod-bias ''" -- "$persp" render --lod-bias= -o "$tmp/a.png"
for spec in "subdiv: 16" "subdiv:+8" "subdiv:0x10" "incremental:k= 4" "incremental:k=" "midpoint:int,int" "constz:eps=0x1p-2"; do
    expect 2 "bad parameters in method '${spec//+/\\+}' \(expected " -- "$persp" render --method "$spec" -o "$tmp/a.png"
done
expect 2 "bad --filter 'aniso:0': aniso taps must be 2..16" -- "$persp" render --filter aniso:0 -o "$tmp/a.png"
expect 2 "bad --filter 'aniso-window:17': aniso taps must be 2..16" -- "$persp" render --filter aniso-window:17 -o "$tmp/a.png"
expect 2 "option --size given more than once" -- "$persp" render --size 8x8 --size 8x8 -o "$tmp/a.png"
expect 2 "option --output given more than once" -- "$persp" render -o "$tmp/a.png" --output "$tmp/b.png"
expect 2 "option --seed given more than once" -- "$persp" accuracy --seed 1 --seed 2
# list options still repeat
expect 0 "affine" -- "$persp" accuracy --case paper-quad --method affine --method exact --triangles 1
# every method spec the docs and `persp methods` show still parses
specs=$(grep -ohE '`(subdiv|incremental|midpoint|constz|adaptive|bezier)(:[^` ]+)?`' "$src/docs/METHODS.md" "$src/README.md" | tr -d '`' | sort -u)
n=0
for spec in $specs; do
    [[ "$spec" == *[A-Z]* || "$spec" == *'|'* || "$spec" == *'...'* ]] && continue
    n=$((n + 1))
    expect 0 "" -- "$persp" render cube --size 8x8 -q --method "$spec" -o "$tmp/a.png"
done
[ "$n" -ge 3 ] && ok || bad "only $n documented specs found"

# ------------------------------------------------------------ write errors
for c in "--help" "--version" "version" "methods" "render --help" "bench --help" "accuracy --help" \
         "merge --help" "report --help" "view --help"; do
    expect 1 "write error on standard output" -- sh -c "\"\$0\" $c >/dev/full" "$persp"
done
expect 1 "write error on standard output|write failed" -- \
    sh -c '"$0" accuracy --case paper-quad --method affine --triangles 1 >/dev/full' "$persp"
expect 1 "/dev/full" -- "$persp" accuracy --case paper-quad --method affine --triangles 1 -o /dev/full
for k in 1 2; do
    expect 0 "" -- "$persp" accuracy --case paper-quad --method affine --triangles 1 --json --shard $k/2 -o "$tmp/acc$k.json"
done
expect 1 "/dev/full" -- "$persp" merge -o /dev/full "$tmp/acc1.json" "$tmp/acc2.json"
expect 1 "/dev/full|write" -- "$persp" bench cube --size 8x8 --frames 1 --reps 1 -o /dev/full

echo "reliability io: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
