#!/usr/bin/env bash
# persp view's window without a display (SDL's dummy video driver): opens,
# draws a few frames and exits 0. Skipped when the window was not built.
persp="$1"
. "$(dirname "$0")/lib.sh"
if "$persp" view --help | grep -q "has no window"; then
    echo "view window: skipped (built without SDL2 / Dear ImGui)"
    expect 1 "built without the window" -- "$persp" view cube --frames 1
    exit 0
fi
# No display and no driver asked for: SDL would fall back to its offscreen
# driver and the window would run invisibly until killed; it is refused.
# persp says so before SDL starts, whose Wayland probe would print its own
# "error: XDG_RUNTIME_DIR is invalid" first: persp's line is the only one.
out=$(env -u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER -u XDG_RUNTIME_DIR SDL_AUDIODRIVER=dummy \
    timeout 20 "$persp" view cube --frames 1 2>&1); rc=$?
[ "$rc" -eq 1 ] && [ "$(wc -l <<<"$out")" -eq 1 ] && grep -q "^persp: view: cannot open a window" <<<"$out" &&
    ok || bad "no display: rc $rc: $out"
export SDL_VIDEODRIVER=dummy SDL_AUDIODRIVER=dummy
expect 0 "" -- "$persp" view cube --frames 3 --size 320x240 -q
for layout in single split diff; do
    expect 0 "" -- "$persp" view corridor --frames 2 --size 200x150 --layout "$layout" \
        --method subdiv:8 --count-ops -q
done
# The window's read-back, panels included, is a PNG of the window's size.
expect 0 "" -- "$persp" view floor --frames 2 --size 400x300 --window-shot "$tmp/win.png" -q
if [ -s "$tmp/win.png" ] && [ "$(head -c 8 "$tmp/win.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; then
    ok
else
    bad "no PNG from --window-shot"
fi
w=$(od -An -tu1 -j16 -N8 "$tmp/win.png" | awk '{print $3*256+$4 "x" $7*256+$8}')
[ "$w" = 400x300 ] && ok || bad "window shot is $w, expected 400x300"
expect 1 "no-such-dir" -- "$persp" view floor --frames 1 --size 64x48 --window-shot "$tmp/no-such-dir/x.png" -q
# A script's first action is taken on the first frame shown (a screenshot
# then was lost), into the default folder out/frames, made with its parent.
mkdir -p "$tmp/shot" && printf 'key P\n' >"$tmp/shot/s.txt"
(cd "$tmp/shot" && "$persp" view corridor --size 96x72 --script s.txt -q) && [ -s "$tmp/shot/out/frames/view_0000.png" ] &&
    ok || bad "first-action screenshot: $(ls -R "$tmp/shot")"
# Free-running (the render thread, no --frames): SIGTERM arrives as SDL's
# quit event and the window closes cleanly.
if command -v timeout >/dev/null; then
    timeout --preserve-status -s TERM 2 "$persp" view corridor --size 160x120 --method affine -q \
        >"$tmp/run.out" 2>&1
    rc=$?
    [ "$rc" -eq 0 ] && ok || bad "free-running window exited $rc: $(cat "$tmp/run.out")"
fi
echo "view window: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
