#!/usr/bin/env python3
"""Generates the example scenes' textures and the room model.

Everything under scenes/textures/ and scenes/models/, and the texture of the
workloads in scenes/bench/ (a copy of checker.png: a scene reads files only
from its own folder and below), is produced here from
code, deterministically (no randomness beyond a fixed integer hash), so the
assets can be regenerated and reviewed. Standard library only.

    python3 scenes/tools/make_assets.py          # writes into scenes/
"""
import math
import os
import struct
import sys
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def write_png(path, w, h, pixel):
    """pixel(x, y) -> (r, g, b) with y = 0 the top row of the image."""
    raw = bytearray()
    for y in range(h):
        raw.append(0)
        for x in range(w):
            r, g, b = pixel(x, y)
            raw += bytes((clamp(r), clamp(g), clamp(b)))

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(raw), 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def clamp(v):
    return max(0, min(255, int(round(v))))


def hash01(*k):
    h = 2166136261
    for v in k:
        h = ((h ^ (v & 0xFFFFFFFF)) * 16777619) & 0xFFFFFFFF
        h ^= h >> 13
    return (h & 0xFFFF) / 65535.0


def mix(a, b, t):
    return tuple(a[i] + (b[i] - a[i]) * t for i in range(3))


# ---------------------------------------------------------------- textures

def wood(x, y):
    """Floor boards: 8 planks across, staggered joints, grain lines."""
    plank = y // 16
    shift = int(hash01(plank, 7) * 128)
    joint = (x + shift) % 128 == 0 or y % 16 == 0
    base = mix((150, 98, 52), (186, 128, 70), hash01(plank, 3))
    grain = 0.5 + 0.5 * math.sin((x + shift) * 0.07 + 3.0 * math.sin(y * 0.9 + plank))
    c = mix(base, (120, 74, 38), 0.35 * grain)
    return (60, 38, 20) if joint else c


def wallpaper(x, y):
    """Cream stripes with small diamonds."""
    stripe = (x // 8) % 2
    c = (226, 214, 184) if stripe else (212, 196, 160)
    dx, dy = abs((x % 32) - 16), abs((y % 32) - 16)
    if dx + dy < 5:
        c = (170, 92, 80)
    return c


def door(x, y):
    """A four-panel door with a brass knob; the texture spans the door."""
    c = (110, 66, 36)
    for (x0, y0, x1, y1) in ((12, 10, 58, 58), (70, 10, 116, 58), (12, 70, 58, 240), (70, 70, 116, 240)):
        if x0 <= x < x1 and y0 <= y < y1:
            edge = min(x - x0, x1 - 1 - x, y - y0, y1 - 1 - y)
            c = (84, 48, 24) if edge < 3 else (128, 80, 44)
    if (x - 106) ** 2 + (y - 140) ** 2 < 30:
        c = (220, 180, 60)
    return mix(c, (90, 55, 30), 0.15 * hash01(x // 2, y // 6))


def carpet_a(x, y):
    """Red rug: border bands and a central medallion."""
    e = min(x, 127 - x, y, 127 - y)
    if e < 6:
        return (60, 30, 30)
    if e < 14:
        return (220, 180, 90) if ((x + y) // 4) % 2 else (120, 30, 36)
    r = math.hypot(x - 63.5, y - 63.5)
    if r < 22:
        return (30, 60, 110) if int(r) % 6 < 3 else (220, 180, 90)
    return (150, 30, 40) if ((x // 8) + (y // 8)) % 2 else (135, 26, 36)


def carpet_b(x, y):
    """Blue-green runner stripes."""
    band = (y // 12) % 3
    return ((40, 90, 120), (60, 130, 110), (200, 190, 150))[band]


def picture_landscape(x, y):
    if min(x, 127 - x, y, 127 - y) < 6:
        return (150, 110, 40)
    hill = 80 + 12 * math.sin(x * 0.07) + 6 * math.sin(x * 0.19 + 1)
    if (x - 90) ** 2 + (y - 30) ** 2 < 120:
        return (250, 220, 90)
    if y > hill:
        return mix((70, 140, 60), (30, 80, 40), (y - hill) / 50.0)
    return mix((120, 170, 230), (220, 235, 250), y / 90.0)


def picture_circles(x, y):
    if min(x, 127 - x, y, 127 - y) < 6:
        return (30, 30, 30)
    for cx, cy, r, c in ((44, 50, 26, (220, 60, 50)), (84, 70, 30, (40, 90, 200)), (60, 96, 16, (240, 200, 40))):
        if (x - cx) ** 2 + (y - cy) ** 2 < r * r:
            return c
    return (236, 232, 220)


def picture_grid(x, y):
    if min(x, 127 - x, y, 127 - y) < 6:
        return (200, 200, 205)
    cell = ((x - 6) // 29, (y - 6) // 29)
    colours = ((230, 40, 40), (250, 250, 245), (30, 60, 170), (250, 210, 40))
    if (x - 6) % 29 < 3 or (y - 6) % 29 < 3:
        return (20, 20, 20)
    return colours[int(hash01(cell[0], cell[1]) * 4) % 4]


def checker(x, y):
    """8×8 checker with a gradient, readable under any distortion."""
    on = ((x // 16) + (y // 16)) % 2
    a = mix((235, 235, 225), (250, 200, 120), x / 127.0)
    b = mix((40, 60, 140), (140, 40, 90), y / 127.0)
    return a if on else b


def stripes(x, y):
    return (240, 240, 240) if (x // 8) % 2 else (200, 50, 40)


def skymap(x, y):
    """A sphere-map-like environment: sky above, ground below, a bright sun."""
    u, v = (x - 63.5) / 63.5, (63.5 - y) / 63.5
    if u * u + v * v > 1.0:
        return (0, 0, 0)
    if (u - 0.35) ** 2 + (v - 0.45) ** 2 < 0.01:
        return (255, 250, 220)
    if v > -0.1:
        return mix((200, 225, 250), (60, 110, 200), (v + 0.1) / 1.1)
    return mix((120, 100, 70), (60, 50, 35), (-v - 0.1) / 0.9)


TEXTURES = {
    "wood.png": (128, 128, wood),
    "wallpaper.png": (64, 64, wallpaper),
    "door.png": (128, 256, door),
    "carpet_a.png": (128, 128, carpet_a),
    "carpet_b.png": (64, 64, carpet_b),
    "picture_landscape.png": (128, 128, picture_landscape),
    "picture_circles.png": (128, 128, picture_circles),
    "picture_grid.png": (128, 128, picture_grid),
    "checker.png": (128, 128, checker),
    "stripes.png": (64, 64, stripes),
    "skymap.png": (128, 128, skymap),
}


# ------------------------------------------------------------------- room

class Obj:
    def __init__(self):
        self.v, self.vt, self.lines = [], [], []
        self.vn = {}

    def quad(self, corners, uvs, normal):
        """Corners anticlockwise seen from the side the normal points to."""
        key = tuple(normal)
        if key not in self.vn:
            self.vn[key] = len(self.vn) + 1
            self.lines.append("vn %g %g %g" % key)
        base_v, base_t = len(self.v), len(self.vt)
        for c in corners:
            self.v.append(c)
            self.lines.append("v %g %g %g" % tuple(c))
        for t in uvs:
            self.vt.append(t)
            self.lines.append("vt %g %g" % tuple(t))
        n = self.vn[key]
        # A quad as one polygon, triangulated by the loader as a fan.
        self.lines.append("f " + " ".join("%d/%d/%d" % (base_v + i + 1, base_t + i + 1, n) for i in range(4)))


def room_obj():
    """Room interior: x in [-3, 3], y in [0, 2.6], z in [-8, 0]. The
    polygons [Romanyuk-PCF] §4.9 names as the common case: floors, walls and
    ceilings, doors, pictures and carpets, all axis-aligned quads."""
    X0, X1, H, Z0, Z1 = -3.0, 3.0, 2.6, -8.0, 0.0
    eps = 0.01
    o = Obj()
    o.lines += ["# persp example room (generated by scenes/tools/make_assets.py)", "mtllib room.mtl", "o room"]

    def face(mtl, group, corners, uvs, normal):
        o.lines.append("g " + group)
        o.lines.append("usemtl " + mtl)
        o.quad(corners, uvs, normal)

    # Floor and ceiling: boards 1 texture repeat per 2 m.
    face("wood", "floor", [(X0, 0, Z1), (X1, 0, Z1), (X1, 0, Z0), (X0, 0, Z0)],
         [(0, 0), (3, 0), (3, 4), (0, 4)], (0, 1, 0))
    face("ceiling", "ceiling", [(X0, H, Z0), (X1, H, Z0), (X1, H, Z1), (X0, H, Z1)],
         [(0, 0), (1, 0), (1, 1), (0, 1)], (0, -1, 0))
    # Walls, seen from inside; wallpaper repeats every 0.8 m.
    r = 1 / 0.8
    face("wall", "wall_back", [(X0, 0, Z0), (X1, 0, Z0), (X1, H, Z0), (X0, H, Z0)],
         [(0, 0), (6 * r, 0), (6 * r, H * r), (0, H * r)], (0, 0, 1))
    face("wall", "wall_front", [(X1, 0, Z1), (X0, 0, Z1), (X0, H, Z1), (X1, H, Z1)],
         [(0, 0), (6 * r, 0), (6 * r, H * r), (0, H * r)], (0, 0, -1))
    face("wall", "wall_left", [(X0, 0, Z1), (X0, 0, Z0), (X0, H, Z0), (X0, H, Z1)],
         [(0, 0), (8 * r, 0), (8 * r, H * r), (0, H * r)], (1, 0, 0))
    face("wall", "wall_right", [(X1, 0, Z0), (X1, 0, Z1), (X1, H, Z1), (X1, H, Z0)],
         [(0, 0), (8 * r, 0), (8 * r, H * r), (0, H * r)], (-1, 0, 0))
    full = [(0, 0), (1, 0), (1, 1), (0, 1)]
    # Doors: one in the left wall, one in the back wall.
    face("door", "door_left", [(X0 + eps, 0, -2.2), (X0 + eps, 0, -3.1), (X0 + eps, 2.05, -3.1), (X0 + eps, 2.05, -2.2)],
         full, (1, 0, 0))
    face("door", "door_back", [(1.0, 0, Z0 + eps), (1.9, 0, Z0 + eps), (1.9, 2.05, Z0 + eps), (1.0, 2.05, Z0 + eps)],
         full, (0, 0, 1))
    # Pictures on the right and back walls.
    face("picture_landscape", "picture_1",
         [(X1 - eps, 1.1, -2.0), (X1 - eps, 1.1, -1.0), (X1 - eps, 2.0, -1.0), (X1 - eps, 2.0, -2.0)], full, (-1, 0, 0))
    face("picture_circles", "picture_2",
         [(X1 - eps, 1.2, -4.6), (X1 - eps, 1.2, -3.6), (X1 - eps, 1.9, -3.6), (X1 - eps, 1.9, -4.6)], full, (-1, 0, 0))
    face("picture_grid", "picture_3",
         [(-1.6, 1.0, Z0 + eps), (-0.4, 1.0, Z0 + eps), (-0.4, 2.0, Z0 + eps), (-1.6, 2.0, Z0 + eps)], full, (0, 0, 1))
    # Carpets: a rug in the middle and a runner towards the back door.
    face("carpet_a", "carpet_rug", [(-1.5, eps, -2.5), (1.5, eps, -2.5), (1.5, eps, -5.5), (-1.5, eps, -5.5)],
         full, (0, 1, 0))
    face("carpet_b", "carpet_runner", [(1.05, eps, -5.8), (1.85, eps, -5.8), (1.85, eps, -7.9), (1.05, eps, -7.9)],
         [(0, 0), (1, 0), (1, 3), (0, 3)], (0, 1, 0))
    return "\n".join(o.lines) + "\n"


def room_mtl():
    m = ["# materials of room.obj (generated by scenes/tools/make_assets.py)"]

    # ka: ambient reflectance as a share of kd. The ceiling takes more: it
    # faces away from the lamps and stands in for the light bounced off the
    # floor, which a local lighting model does not compute.
    def mat(name, kd, tex=None, ks=(0, 0, 0), ns=16, ka=0.25):
        m.append("")
        m.append("newmtl " + name)
        m.append("Ka %g %g %g" % tuple(ka * c for c in kd))
        m.append("Kd %g %g %g" % kd)
        m.append("Ks %g %g %g" % ks)
        m.append("Ns %g" % ns)
        if tex:
            m.append("map_Kd ../textures/" + tex)

    mat("wood", (1, 1, 1), "wood.png", (0.25, 0.25, 0.25), 40)
    mat("ceiling", (0.92, 0.92, 0.88), ka=0.8)
    mat("wall", (1, 1, 1), "wallpaper.png")
    mat("door", (1, 1, 1), "door.png", (0.2, 0.2, 0.2), 30)
    mat("picture_landscape", (1, 1, 1), "picture_landscape.png", (0.3, 0.3, 0.3), 60)
    mat("picture_circles", (1, 1, 1), "picture_circles.png", (0.3, 0.3, 0.3), 60)
    mat("picture_grid", (1, 1, 1), "picture_grid.png", (0.3, 0.3, 0.3), 60)
    mat("carpet_a", (1, 1, 1), "carpet_a.png")
    mat("carpet_b", (1, 1, 1), "carpet_b.png")
    return "\n".join(m) + "\n"


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else ROOT
    tex_dir, model_dir = os.path.join(out, "textures"), os.path.join(out, "models")
    os.makedirs(tex_dir, exist_ok=True)
    os.makedirs(model_dir, exist_ok=True)
    for name, (w, h, fn) in TEXTURES.items():
        write_png(os.path.join(tex_dir, name), w, h, fn)
    bench_dir = os.path.join(out, "bench")
    os.makedirs(bench_dir, exist_ok=True)
    w, h, fn = TEXTURES["checker.png"]
    write_png(os.path.join(bench_dir, "checker.png"), w, h, fn)
    with open(os.path.join(model_dir, "room.obj"), "w") as f:
        f.write(room_obj())
    with open(os.path.join(model_dir, "room.mtl"), "w") as f:
        f.write(room_mtl())


if __name__ == "__main__":
    main()
