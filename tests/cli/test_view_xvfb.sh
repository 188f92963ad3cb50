#!/usr/bin/env bash
# persp view in a real X window (Xvfb), driven by a --script of input events:
# the left method switched to affine, the divider dragged, the difference
# overlay toggled, a flight and a camera-path replay, with screenshots checked
# pixel by pixel. Skipped without Xvfb or without the window build.
persp="$1"
. "$(dirname "$0")/lib.sh"
if "$persp" view --help | grep -q "has no window"; then
    echo "SKIP: view xvfb: persp was built without the window (SDL2 / Dear ImGui)"
    exit 0
fi
if ! command -v Xvfb >/dev/null; then
    echo "SKIP: view xvfb: Xvfb not found (scripts/deps.sh installs xvfb)"
    exit 0
fi
command -v python3 >/dev/null || { echo "SKIP: view xvfb: python3 not found"; exit 0; }
unset SDL_VIDEODRIVER
export SDL_AUDIODRIVER=dummy
data="$(dirname "$0")/data"
W=480 H=360
# Under ASan the window's process also loads the X server's GL driver (Mesa,
# through SDL's renderer), whose allocations LeakSanitizer reports at exit
# from modules persp does not own; the headless --play path, which loads
# none of them, stays leak-checked in cli_test_view_play.
# Each run gets its own server, which names its display itself (-displayfd)
# once it accepts clients: no lock-file race between parallel tests, and no
# xvfb-run, whose clean-up of its Xauthority folder fails now and then with
# exit 5 whatever the program under test returned.
xrun() {
    local fd="$tmp/display.$BASHPID" xpid rc i
    : >"$fd"
    Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>"$fd" 2>>"$tmp/xvfb.log" &
    xpid=$!
    for ((i = 0; i < 200; i++)); do
        [ -s "$fd" ] && break
        kill -0 "$xpid" 2>/dev/null || break
        sleep 0.05
    done
    if ! [ -s "$fd" ]; then
        echo "Xvfb did not start: $(tail -n 3 "$tmp/xvfb.log")"
        kill "$xpid" 2>/dev/null; wait "$xpid" 2>/dev/null
        return 125
    fi
    DISPLAY=":$(head -n 1 "$fd")" \
        ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" "$@"
    rc=$?
    kill "$xpid" 2>/dev/null; wait "$xpid" 2>/dev/null
    return "$rc"
}

# The split with both sides exact, then the left side affine; the divider
# dragged from the middle to a quarter; the overlay on (window read-back),
# off again; a short flight forward; a camera path replayed to its end.
cat >"$tmp/main.txt" <<EOF
key F1                       # the panel away from the image
method left exact
settle
image $tmp/exact_exact.png
method left affine
settle
image $tmp/affine_exact.png
shot $tmp/split_win.png
drag $((W / 2)) $((W / 4))
settle
image $tmp/divider.png
key H
settle
shot $tmp/overlay_win.png
key H
settle
shot $tmp/plain_win.png
hold W 10
settle
image $tmp/flown.png
play $data/camera_path.json
settle
image $tmp/played.png
EOF
expect 0 "" -- xrun "$persp" view corridor --size ${W}x${H} --script "$tmp/main.txt" -q
# The left side alone, exact: what the split with two exact sides must equal.
printf 'method left exact\nsettle\nimage %s\n' "$tmp/single.png" >"$tmp/single.txt"
expect 0 "" -- xrun "$persp" view corridor --size ${W}x${H} --layout single \
    --script "$tmp/single.txt" -q
# The same path headless: its last frame is the replay's end.
expect 0 "" -- "$persp" view corridor --size ${W}x${H} --method affine --divider 0.25 \
    --play "$data/camera_path.json" --frames 3 -o "$tmp/played" -q
# A script it cannot read fails with its line.
printf 'key F1\nfrobnicate 3\n' >"$tmp/bad.txt"
expect 1 "bad.txt:2: cannot read 'frobnicate 3'" -- xrun "$persp" view corridor \
    --size 64x48 --script "$tmp/bad.txt"

# A signal while a screenshot is written. SDL makes SIGINT/SIGTERM its quit
# event, so the image is finished and the window closes; where SDL installs
# no handlers (SDL_NO_SIGNAL_HANDLERS=1), the CLI's remove the temporary file
# and the process dies of the signal, as render does.
sig_window() { # sig_window SIGNAL FILE -- view arguments...
    local sig="$1" file="$2"; shift 3
    "$persp" view "$@" & local pid=$!
    for _ in $(seq 1 3000); do compgen -G "$file.tmp-*" >/dev/null && break; sleep 0.01; done
    if ! compgen -G "$file.tmp-*" >/dev/null; then wait "$pid"; echo "$sig: no temporary file seen"; return 1; fi
    sleep 0.05
    kill -"$sig" "$pid"; wait "$pid"; local rc=$?
    if compgen -G "$file.tmp-*" >/dev/null; then echo "$sig: left $(ls "$file".tmp-*)"; return 1; fi
    echo "exit $rc"
    [ -e "$file" ] && echo "written"
    return 0
}
mkdir -p "$tmp/sig"
printf 'settle\nimage %s\n' "$tmp/sig/big.png" >"$tmp/sig.txt"
SDL_NO_SIGNAL_HANDLERS=1 expect 0 "^exit 143$" -- \
    xrun sig_window TERM "$tmp/sig/big.png" -- corridor --size 2048x2048 --script "$tmp/sig.txt" -q
[ ! -e "$tmp/sig/big.png" ] && ok || bad "a screenshot killed by SIGTERM was left"
rm -f "$tmp/sig/"*
expect 0 "^written$" -- xrun sig_window INT "$tmp/sig/big.png" -- corridor --size 2048x2048 \
    --script "$tmp/sig.txt" -q
[ "$(head -c 4 "$tmp/sig/big.png" | od -An -c | tr -d ' ')" = '211PNG' ] && ok ||
    bad "the screenshot finished after SIGINT is no PNG"

PYTHONPATH="$(dirname "$0")" python3 - "$tmp" "$W" "$H" <<'PY' && ok || bad "pixel checks of the screenshots"
import sys

tmp, W, H = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])

from png_rows import png

fails = []
def check(cond, what):
    if not cond: fails.append(what)

def cols(img, x0, x1):
    return [row[x0:x1] for row in img[2]]

def share_diff(a, b):
    n = d = 0
    for ra, rb in zip(a, b):
        for pa, pb in zip(ra, rb):
            n += 1
            d += pa != pb
    return d / max(n, 1)

ee, ae, dv = png(f"{tmp}/exact_exact.png"), png(f"{tmp}/affine_exact.png"), png(f"{tmp}/divider.png")
single = png(f"{tmp}/single.png")
for name, img in (("exact_exact", ee), ("affine_exact", ae), ("divider", dv)):
    check(img[:2] == (W, H), f"{name} is {img[0]}x{img[1]}")
half = W // 2
# Both sides exact: the split is the exact image itself, bit for bit.
check(ee[2] == single[2], "split exact | exact differs from the single exact image")
# Affine | exact: the right half is exact's, the left half differs strongly.
check(cols(ae, half, W) == cols(ee, half, W), "right half of affine | exact is not exact's")
d = share_diff(cols(ae, 0, half), cols(ee, 0, half))
check(d > 0.2, f"left half affine vs exact: only {d:.1%} of pixels differ")
# The divider dragged to a quarter of the width.
q = W // 4
check(cols(dv, 0, q) == cols(ae, 0, q), "left of the dragged divider is not affine")
check(cols(dv, q, W) == cols(ee, q, W), "right of the dragged divider is not exact")
# The flight moved the camera; the replay ends where the headless player does.
check(share_diff(png(f"{tmp}/flown.png")[2], dv[2]) > 0.2, "flying forward changed nothing")
check(png(f"{tmp}/played.png")[2] == png(f"{tmp}/played/frame_0002.png")[2],
      "the window's replay differs from --play's last frame")
# The window: its size, and the overlay's legend bottom left (a heat ramp from
# blue to red) where the plain window shows the image.
ov, plain, win = png(f"{tmp}/overlay_win.png"), png(f"{tmp}/plain_win.png"), png(f"{tmp}/split_win.png")
check(ov[:2] == (W, H) and win[:2] == (W, H), "window shots are not the window's size")
ramp = ov[2][H - 84 + 7][10:266]
check(len(set(ramp)) >= 16, f"legend ramp has {len(set(ramp))} colours")
check(ramp[8][2] > ramp[8][0] and ramp[-4][0] > 200 and ramp[-4][2] < 80,
      f"legend ramp runs {ramp[8]} .. {ramp[-4]}, not blue .. red")
check(ov[2][H - 84 + 7][10:266] != plain[2][H - 84 + 7][10:266], "legend missing from the window")
# Away from the HUD, the labels and the divider the window shows the frame itself.
band = slice(H // 2 - 20, H - 40)  # below the HUD, above the labels
for x0, x1 in ((20, half - 20), (half + 20, W - 20)):
    check([r[x0:x1] for r in win[2][band]] == [r[x0:x1] for r in ae[2][band]],
          f"columns {x0}..{x1} of the window are not the rendered frame")
for f in fails:
    print("FAIL:", f)
sys.exit(1 if fails else 0)
PY
echo "view xvfb: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
