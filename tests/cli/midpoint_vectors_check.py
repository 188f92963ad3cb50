#!/usr/bin/env python3
"""A second model of midpoint:int, written from docs/METHODS.md alone
("Fixed-point model" and "Test vectors"), that checks a file of
`persp vectors`: the fixed-point planes from set-up's planes, every span's
start values, and every pixel's lattice indices, W, steps, re-seeds and
outputs. Python integers do not overflow, so any product persp's 64-bit
registers would get wrong shows up as a difference.

Usage: midpoint_vectors_check.py FILE  -> prints counts, exit 1 on the first
difference (naming the line)."""
import math
import struct
import sys
from fractions import Fraction

DEN_BITS = 42
ITER_CAP = 32
N_LIMIT = 1 << 16
L43 = 1 << 43
L58 = 1 << 58


def rnd(x):
    """Half away from zero, exactly (C llround)."""
    f = Fraction(x)
    n = math.floor(abs(f) + Fraction(1, 2))
    return n if f >= 0 else -n


def f32(x):
    return struct.unpack("<I", struct.pack("<f", x))[0]


def floor_div(a, b):
    return a // b  # Python's // floors, as the format's floor_div


class Bad(Exception):
    pass


def expect(cond, lineno, what):
    if not cond:
        raise Bad("line %d: %s" % (lineno, what))


def check_format(plane, fmt, lineno):
    in_format, s, o2 = fmt[0], fmt[1], fmt[2]
    G, H, I = fmt[3:6]
    AB = fmt[6:12]
    X2max, Y2max = fmt[12], fmt[13]
    P = fmt[14:16]
    if not in_format:
        return
    a, b, c, d, e, f, g, h, i = plane
    mx = abs(g) * X2max + abs(h) * Y2max + 2.0 * abs(i)
    ex = math.frexp(mx)[1]
    expect(s == DEN_BITS - ex, lineno, "shift %d, expected %d" % (s, DEN_BITS - ex))
    sc = lambda v: rnd(math.ldexp(v, s))
    expect((G, H, I) == (sc(g), sc(h), sc(i)), lineno, "G, H, I")
    for v in (G, H, I):
        expect(abs(v) < L43, lineno, "|G|, |H|, |I| < 2^43")
    num = ((a, b, c), (d, e, f))
    for j in range(2):
        A, B, C = AB[3 * j:3 * j + 3]
        want = tuple(rnd(math.ldexp(P[j] * v, s)) for v in num[j])
        expect((A, B, C) == want, lineno, "A, B, C of %s: %s, expected %s" % ("uv"[j], (A, B, C), want))
        expect(abs(A) * X2max + abs(B) * Y2max + 2 * abs(C) < L58, lineno, "|N2| < 2^58 over the box")


def start(A, B, C, G, E, X2, Y2, o2):
    N2 = A * X2 + B * Y2 + 2 * C
    n = floor_div(2 * N2 + (1 - o2) * E, 2 * E)
    M = 2 * n + o2
    return N2, n, M * E - 2 * N2 + E, 2 * G * M, 4 * A - 2 * G


def search(st, E, G):
    """st = [n, W, T]; returns steps taken, or None past the cap."""
    it = 0
    n0 = st[0]
    while st[1] <= 0 and it < ITER_CAP:
        st[0] += 1
        st[1] += 2 * E
        st[2] += 4 * G
        it += 1
    while st[1] > 2 * E and it < ITER_CAP:
        st[0] -= 1
        st[1] -= 2 * E
        st[2] -= 4 * G
        it += 1
    if it >= ITER_CAP and not (0 < st[1] <= 2 * E):
        return None
    return st[0] - n0


def check_span(fmt, span, pixels, lineno, counts):
    o2, G, H, I = fmt[2], fmt[3], fmt[4], fmt[5]
    AB = fmt[6:12]
    X2max, Y2max = fmt[12], fmt[13]
    P = fmt[14:16]
    x0, y, n, int_pixels = span[:4]
    expect(len(pixels) == n, lineno, "%d pixel lines for a span of %d" % (len(pixels), n))
    X2, Y2 = 2 * x0 + 1, 2 * y + 1
    E = G * X2 + H * Y2 + 2 * I
    Eend = E + 2 * G * (n - 1)
    # Where the integer path applies at all (docs: pixels inside the box, E > 0,
    # both first indices inside the texel range).
    ok = fmt[0] and x0 >= 0 and y >= 0 and 2 * (x0 + n) - 1 < X2max and Y2 < Y2max and E > 0 and Eend > 0
    st = []
    if ok:
        for j in range(2):
            A, B, C = AB[3 * j:3 * j + 3]
            N2, n0, W0, T0, K = start(A, B, C, G, E, X2, Y2, o2)
            if not (-N_LIMIT < n0 < N_LIMIT):
                ok = False
                break
            st.append([n0, W0, T0, K, A, B, C])
    if not ok:
        expect(int_pixels == 0, lineno, "span runs the integer path (%d pixels) outside its limits" % int_pixels)
        counts["double_spans"] += 1
    else:
        expect(span[4] == E, lineno, "E0 %d, expected %d" % (span[4], E))
        for j in range(2):
            got = span[5 + 5 * j:10 + 5 * j]
            A, B, C = st[j][4:7]
            want = start(A, B, C, G, E, X2, Y2, o2)
            expect(tuple(got) == want, lineno, "start of %s %s, expected %s" % ("uv"[j], tuple(got), want))
    ended = None
    for k in range(n):
        kind, vals, pl = pixels[k]
        if ok and ended is None:
            if k > 0:
                E += 2 * G
                for j in range(2):
                    st[j][1] += st[j][2] - st[j][3]
            rec = []
            for j in range(2):
                s = st[j]
                steps = search(s, E, G)
                reseed = 0
                if steps is None:
                    A, B, C = s[4:7]
                    N2 = A * (X2 + 2 * k) + B * Y2 + 2 * C
                    nn = floor_div(2 * N2 + (1 - o2) * E, 2 * E)
                    if not (-N_LIMIT < nn < N_LIMIT):
                        ended = k
                        break
                    s[0], s[1], s[2] = nn, (2 * nn + o2) * E - 2 * N2 + E, 2 * G * (2 * nn + o2)
                    steps = search(s, E, G)
                    reseed = 1
                    counts["reseeds"] += 1
                if not (-N_LIMIT < s[0] < N_LIMIT):
                    ended = k
                    break
                rec.append((s[0], s[1], steps, reseed))
            if ended is None:
                expect(kind == "px", pl, "pixel %d of the span: %s, expected an integer pixel" % (k, kind))
                want = [v for r in rec for v in r]
                expect(vals[:8] == want, pl, "pixel state %s, expected %s" % (vals[:8], want))
                for j in range(2):
                    out = f32((rec[j][0] + 0.5 * o2) * (1.0 / P[j]))
                    expect(vals[8 + j] == out, pl, "output %s %08x, expected %08x" % ("uv"[j], vals[8 + j], out))
                counts["int_pixels"] += 1
                counts["steps"] += abs(rec[0][2]) + abs(rec[1][2])
                continue
            counts["fallbacks"] += 1
            expect(int_pixels == ended, lineno, "integer path ends at pixel %d, expected %d" % (int_pixels, ended))
        expect(kind == "dpx", pl, "pixel %d of the span: %s, expected a double-path pixel" % (k, kind))
        counts["double_pixels"] += 1
    if ok and ended is None:
        expect(int_pixels == n, lineno, "integer pixels %d of %d" % (int_pixels, n))


def main(path):
    counts = dict(triangles=0, spans=0, int_pixels=0, double_pixels=0, double_spans=0, reseeds=0,
                  fallbacks=0, steps=0)
    plane = fmt = None
    span = None
    span_line = 0
    pixels = []
    summary = None

    def flush():
        if span is not None:
            check_span(fmt, span, pixels, span_line, counts)

    with open(path) as fh:
        for lineno, line in enumerate(fh, 1):
            w = line.split()
            if not w:
                continue
            if w[0] == "#":
                if len(w) > 2 and w[2] == "triangles,":
                    summary = line
                continue
            if w[0] in ("tri", "plane", "fmt", "span"):
                flush()
                span = None
                pixels = []
            if w[0] == "tri":
                expect(len(w) == 17, lineno, "tri: 17 fields")
                counts["triangles"] += 1
            elif w[0] == "plane":
                expect(len(w) == 10, lineno, "plane: 10 fields")
                plane = [float.fromhex(x) for x in w[1:]]
            elif w[0] == "fmt":
                expect(len(w) == 17, lineno, "fmt: 17 fields")
                fmt = [int(x) for x in w[1:15]] + [float(x) for x in w[15:17]]
                check_format(plane, fmt, lineno)
            elif w[0] == "span":
                expect(len(w) == 16, lineno, "span: 16 fields")
                span = [int(x) for x in w[1:]]
                span_line = lineno
                counts["spans"] += 1
            elif w[0] == "px":
                expect(len(w) == 11, lineno, "px: 11 fields")
                pixels.append(("px", [int(x) for x in w[1:9]] + [int(x, 16) for x in w[9:11]], lineno))
            elif w[0] == "dpx":
                expect(len(w) == 3, lineno, "dpx: 3 fields")
                pixels.append(("dpx", [int(x, 16) for x in w[1:3]], lineno))
            else:
                raise Bad("line %d: unknown record %r" % (lineno, w[0]))
        flush()
    expect(summary is not None, 0, "no closing summary line")
    print(" ".join("%s=%d" % kv for kv in counts.items()))


if __name__ == "__main__":
    try:
        main(sys.argv[1])
    except Bad as e:
        print("%s: %s" % (sys.argv[1], e))
        sys.exit(1)
