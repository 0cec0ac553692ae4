#!/usr/bin/env python3
"""Writes the heritage demo's glTF 2.0 models (metres, Y-up: x east, y up, -z north).

    python3 apps/demos/heritage/make_heritage.py [OUT_DIR]     # default: this script's folder

  kalabsha.gltf + .bin   the temple of Mandulis at New Kalabsha (Ptolemaic/Roman, re-erected
                         1961-63 by the Aswan High Dam): causeway and terrace, a battered pylon
                         with its gateway, the forecourt with colonnades on three sides, the
                         hypostyle hall (its screen-walled facade, eight columns, a roof), two
                         vestibules, the sanctuary, the enclosure wall; a sandstone promontory
                         with the lake to the east. Node "kalabsha_temple" (the building) is
                         rotated so that its axis, from the sanctuary out through the gateway,
                         points at azimuth KALABSHA_AXIS_AZIMUTH_DEG.
  kiti.gltf + .bin       Panagia Angeloktisti at Kiti (Cyprus): a small cross-in-square church
                         with its semicircular apse (a half dome over it), barrel vaults over
                         the four arms, a dome on a windowed drum over the crossing, a lower
                         narthex to the west and the barrel-vaulted chapel of Saints Kosmas
                         and Damian along the north side; doors and windows let daylight in. Node
                         "kiti_church", its apse towards KITI_APSE_AZIMUTH_DEG.

Both models are built in a local frame whose +x is the building's axis (the way out through
the Kalabsha gateway; towards the apse at Kiti), +z to the right of it, and turned into place
by a rotation about +y of (90 - azimuth) degrees. The demo (apps/welkin/heritage.cpp) keeps the
same azimuths; a test checks the files against them.

Dimensions are modelled after published descriptions (the Kalabsha temple house is about 76 m
long and 22 m wide, its court colonnaded and its hypostyle hall of eight columns; the Kiti
church is a small 11th-century domed cross-in-square church), not surveyed plans: the models
are meant to be recognisable, not measured.

Plain python3: the glTF writer (Gltf, MeshBuilder) is the host example's
(examples/host/assets/make_assets.py); the same script writes the same bytes every time.
"""
import importlib.util
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location(
    "make_assets", os.path.join(HERE, "..", "..", "..", "examples", "host", "assets", "make_assets.py"))
_assets = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_assets)
Gltf, MeshBuilder, smoothstep = _assets.Gltf, _assets.MeshBuilder, _assets.smoothstep

# Azimuths (degrees from north through east); apps/welkin/heritage.cpp holds the same numbers.
KALABSHA_AXIS_AZIMUTH_DEG = 100.0
KITI_APSE_AZIMUTH_DEG = 90.0

# Linear albedos (base colours).
SANDSTONE = (0.46, 0.33, 0.19)      # Nubian sandstone, yellow-brown
SANDSTONE_DARK = (0.36, 0.25, 0.14)  # the same, for the terrace and the column drums
GRANITE = (0.13, 0.10, 0.085)       # the dark granite of the promontory
DESERT = (0.50, 0.34, 0.18)         # wind-blown orange sand
WATER = (0.010, 0.020, 0.025)       # lake water (the reflection does the rest)
LIMESTONE = (0.48, 0.41, 0.30)      # Cypriot limestone ashlar
PLASTER = (0.55, 0.50, 0.42)        # the lime-plastered vaults and dome
EARTH = (0.20, 0.15, 0.095)         # the dry fields around Kiti
SCRUB = (0.06, 0.075, 0.035)


# ---------------------------------------------------------------- solids (flat-shaded)

def face(mb, pts, inside):
    """A planar convex polygon whose normal points away from the point `inside`."""
    ax, ay, az = (pts[1][k] - pts[0][k] for k in range(3))
    bx, by, bz = (pts[2][k] - pts[0][k] for k in range(3))
    n = (ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx)
    c = [sum(p[k] for p in pts) / len(pts) for k in range(3)]
    if sum(n[k] * (c[k] - inside[k]) for k in range(3)) < 0:
        pts = list(reversed(pts))
    mb.polygon(pts)


def dedupe(pts):
    """Drops repeated corners (a quad whose edge shrank to a point is a triangle)."""
    out = []
    for p in pts:
        if not out or max(abs(p[k] - out[-1][k]) for k in range(3)) > 1e-9:
            out.append(p)
    while len(out) > 1 and max(abs(out[0][k] - out[-1][k]) for k in range(3)) <= 1e-9:
        out.pop()
    return out


def both(mb, pts):
    """A thin shell seen from both sides (the renderer culls back faces)."""
    pts = dedupe(pts)
    if len(pts) < 3:
        return
    mb.polygon(pts)
    mb.polygon(list(reversed(pts)))


def prism(mb, bottom, top, faces_bottom=False):
    """A convex solid between two convex quads/polygons of the same vertex count."""
    n = len(bottom)
    inside = [sum(p[k] for p in bottom + top) / (2 * n) for k in range(3)]
    for i in range(n):
        j = (i + 1) % n
        face(mb, [bottom[i], bottom[j], top[j], top[i]], inside)
    face(mb, list(top), inside)
    if faces_bottom:
        face(mb, list(bottom), inside)


def box(mb, x0, x1, y0, y1, z0, z1, bottom=True):
    b = [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)]
    t = [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)]
    prism(mb, b, t, bottom)


def cylinder(mb, cx, cz, r0, r1, y0, y1, n=10):
    """A column drum (or a capital: r1 != r0) with n flat sides."""
    b = [(cx + r0 * math.cos(2 * math.pi * i / n), y0, cz + r0 * math.sin(2 * math.pi * i / n)) for i in range(n)]
    t = [(cx + r1 * math.cos(2 * math.pi * i / n), y1, cz + r1 * math.sin(2 * math.pi * i / n)) for i in range(n)]
    prism(mb, b, t)


def column(mb, cx, cz, r, h):
    """An Egyptian column: base disc, shaft, a flared (campaniform) capital and an abacus."""
    cylinder(mb, cx, cz, r * 1.25, r * 1.25, 0.0, 0.3)
    cylinder(mb, cx, cz, r, r * 0.92, 0.3, h * 0.78)
    cylinder(mb, cx, cz, r * 0.92, r * 1.45, h * 0.78, h * 0.94)
    box(mb, cx - r * 0.9, cx + r * 0.9, h * 0.94, h, cz - r * 0.9, cz + r * 0.9)


def curved_wall(mb, cx, cz, r_in, r_out, a0, a1, y0, y1, n):
    """A thick wall along a circular arc about (cx, cz) from angle a0 to a1 (radians, in the
    x-z plane: x = cx + r cos a, z = cz + r sin a), n segments, each a small convex solid."""
    for i in range(n):
        t0, t1 = a0 + (a1 - a0) * i / n, a0 + (a1 - a0) * (i + 1) / n
        pts = lambda r, t, y: (cx + r * math.cos(t), y, cz + r * math.sin(t))
        bottom = [pts(r_in, t0, y0), pts(r_out, t0, y0), pts(r_out, t1, y0), pts(r_in, t1, y0)]
        top = [pts(r_in, t0, y1), pts(r_out, t0, y1), pts(r_out, t1, y1), pts(r_in, t1, y1)]
        prism(mb, bottom, top)


def barrel_vault(mb, axis, a0, a1, c, y_spring, r, n=12):
    """A semicircular barrel vault (thin, two-sided) of radius r springing at y_spring, its axis
    along x (axis="x": from x = a0 to a1, centred on z = c) or along z."""
    for i in range(n):
        t0, t1 = math.pi * i / n, math.pi * (i + 1) / n
        u0, v0 = r * math.cos(t0), y_spring + r * math.sin(t0)
        u1, v1 = r * math.cos(t1), y_spring + r * math.sin(t1)
        if axis == "x":
            both(mb, [(a0, v0, c + u0), (a1, v0, c + u0), (a1, v1, c + u1), (a0, v1, c + u1)])
        else:
            both(mb, [(c + u0, v0, a0), (c + u0, v0, a1), (c + u1, v1, a1), (c + u1, v1, a0)])


def vault_end(mb, axis, a, c, y_spring, r, n=12):
    """The semicircular tympanum closing a barrel vault's end (thin, two-sided)."""
    for i in range(n):
        t0, t1 = math.pi * i / n, math.pi * (i + 1) / n
        if axis == "x":
            both(mb, [(a, y_spring, c), (a, y_spring + r * math.sin(t0), c + r * math.cos(t0)),
                      (a, y_spring + r * math.sin(t1), c + r * math.cos(t1))])
        else:
            both(mb, [(c, y_spring, a), (c + r * math.cos(t0), y_spring + r * math.sin(t0), a),
                      (c + r * math.cos(t1), y_spring + r * math.sin(t1), a)])


def spandrel(mb, axis, a, c, y_spring, r, y_top, n=12):
    """The wall between a semicircular arch (radius r, springing at y_spring, in the plane
    x = a for axis "x", z = a for axis "z", centred on c) and the level y_top above it."""
    for i in range(n):
        t0, t1 = math.pi * i / n, math.pi * (i + 1) / n
        u0, v0 = c + r * math.cos(t0), y_spring + r * math.sin(t0)
        u1, v1 = c + r * math.cos(t1), y_spring + r * math.sin(t1)
        if axis == "x":
            both(mb, [(a, v0, u0), (a, v1, u1), (a, y_top, u1), (a, y_top, u0)])
        else:
            both(mb, [(u0, v0, a), (u1, v1, a), (u1, y_top, a), (u0, y_top, a)])


def dome(mb, cx, y0, cz, r, a0=0.0, a1=2 * math.pi, n_az=16, n_el=6, ky=1.0):
    """A (part of a) hemispherical dome (thin, two-sided) over azimuths a0..a1 in the x-z plane,
    its height ky r (ky < 1: a flattened dome)."""
    for j in range(n_el):
        e0, e1 = 0.5 * math.pi * j / n_el, 0.5 * math.pi * (j + 1) / n_el
        for i in range(n_az):
            t0, t1 = a0 + (a1 - a0) * i / n_az, a0 + (a1 - a0) * (i + 1) / n_az
            p = lambda t, e: (cx + r * math.cos(e) * math.cos(t), y0 + ky * r * math.sin(e), cz + r * math.cos(e) * math.sin(t))
            if j == n_el - 1:
                both(mb, [p(t0, e0), p(t1, e0), p(t0, e1)])
            else:
                both(mb, [p(t0, e0), p(t1, e0), p(t1, e1), p(t0, e1)])


# ---------------------------------------------------------------- ground

def ground(g, name, half, n, height, colour, material):
    """A heightfield n x n over [-half, half]^2 with per-vertex normals and colours."""
    pos, nor, col = [], [], []
    for j in range(n):
        z = -half + 2 * half * j / (n - 1)
        for i in range(n):
            x = -half + 2 * half * i / (n - 1)
            y = height(x, z)
            pos.append((x, y, z))
            e = 1.0
            hx = (height(x + e, z) - height(x - e, z)) / (2 * e)
            hz = (height(x, z + e) - height(x, z - e)) / (2 * e)
            l = math.sqrt(hx * hx + 1 + hz * hz)
            nor.append((-hx / l, 1 / l, -hz / l))
            col.append(colour(x, y, z))
    idx = []
    for j in range(n - 1):
        for i in range(n - 1):
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i, (j + 1) * n + i + 1
            idx += [a, c, b, b, c, d]
    prim = {"attributes": {"POSITION": g.vec3(pos, True), "NORMAL": g.vec3(nor), "COLOR_0": g.color_u8(col)},
            "indices": g.indices(idx), "material": material, "mode": 4}
    g.node(name, g.mesh(name, [prim]))


def flat(g, name, half, y, material):
    mb = MeshBuilder()
    mb.polygon([(-half, y, half), (half, y, half), (half, y, -half), (-half, y, -half)])
    g.node(name, g.mesh(name, [mb.primitive(g, material)]))


def mix(a, b, t):
    return tuple(a[k] * (1 - t) + b[k] * t for k in range(3))


# ---------------------------------------------------------------- Kalabsha

def kalabsha_temple(stone, dark):
    """Local frame: +x out through the gateway, the pylon's outer face at x = 0."""
    # Causeway from the lake up to a terrace before the pylon.
    box(dark, 6.0, 70.0, -4.0, 0.4, -4.0, 4.0)
    box(dark, 0.0, 12.0, -4.0, 0.4, -14.0, 14.0)
    # The pylon: two battered towers 15 m high, the gateway between them.
    for s in (-1, 1):
        zi, zo = 2.6 * s, 17.0 * s   # inner (gateway side) and outer ends
        zo_top = zo - 1.4 * s        # the batter: the outer end leans in 1.4 m
        bottom = [(-5.0, 0.0, zi), (0.0, 0.0, zi), (0.0, 0.0, zo), (-5.0, 0.0, zo)]
        top = [(-4.4, 15.0, zi), (-0.6, 15.0, zi), (-0.6, 15.0, zo_top), (-4.4, 15.0, zo_top)]
        prism(stone, bottom, top)
        box(stone, -4.6, -0.4, 15.0, 15.6, min(zi, zo_top), max(zi, zo_top))  # cornice
    # The gateway: jambs and the lintel block over a 3.2 m wide, 7 m high door.
    for s in (-1, 1):
        box(stone, -5.2, 0.3, 0.0, 11.0, 1.6 * s if s > 0 else -2.6, 2.6 if s > 0 else -1.6)
    box(stone, -5.2, 0.3, 7.0, 11.0, -1.6, 1.6)
    # The forecourt (x in [-25, -5]): side walls, colonnades on the north, south and west sides
    # with a roof over each walk.
    box(stone, -25.0, -5.0, 0.0, 7.5, -12.0, -11.0)
    box(stone, -25.0, -5.0, 0.0, 7.5, 11.0, 12.0)
    for x in (-8.0, -11.5, -15.0, -18.5, -22.0):
        for z in (-8.2, 8.2):
            column(stone, x, z, 0.55, 6.5)
    for z in (-5.0, 5.0):
        column(stone, -23.0, z, 0.55, 6.5)
    box(stone, -25.0, -6.0, 6.5, 7.2, -11.0, -7.4)
    box(stone, -25.0, -6.0, 6.5, 7.2, 7.4, 11.0)
    # The hypostyle hall (x in [-38, -25]): its facade of four columns joined by screen walls
    # half their height (Ptolemaic style), four more columns inside, a roof.
    for z in (-6.0, -2.2, 2.2, 6.0):
        column(stone, -25.5, z, 0.7, 10.0)
        column(stone, -31.5, z, 0.7, 10.0)
    for z0, z1 in ((-11.0, -6.6), (-5.4, -2.8), (2.8, 5.4), (6.6, 11.0)):
        box(stone, -26.0, -25.0, 0.0, 4.5, z0, z1)
    box(stone, -38.0, -25.0, 0.0, 11.0, -12.0, -11.0)
    box(stone, -38.0, -25.0, 0.0, 11.0, 11.0, 12.0)
    box(stone, -38.0, -24.6, 10.0, 11.2, -12.0, 12.0)   # roof slabs on the architraves
    box(stone, -26.2, -24.6, 8.0, 10.0, -12.0, 12.0)    # the facade's architrave and cornice band
    # Back wall of the hall with the door to the vestibules.
    box(stone, -39.0, -38.0, 0.0, 11.0, -12.0, -1.3)
    box(stone, -39.0, -38.0, 0.0, 11.0, 1.3, 12.0)
    box(stone, -39.0, -38.0, 4.8, 11.0, -1.3, 1.3)
    # Two vestibules and the sanctuary, stepping down in height; doors on the axis.
    rooms = [(-47.0, -39.0, 9.5), (-55.0, -47.0, 8.8), (-66.0, -55.0, 8.0)]
    for k, (x0, x1, h) in enumerate(rooms):
        box(stone, x0, x1, 0.0, h, -9.0, -8.0)
        box(stone, x0, x1, 0.0, h, 8.0, 9.0)
        box(stone, x0 - 0.2, x1, h, h + 0.8, -9.0, 9.0)  # roof
        if k < 2:  # the wall between this room and the next, with its door
            box(stone, x0 - 1.0, x0, 0.0, h, -8.0, -1.1)
            box(stone, x0 - 1.0, x0, 0.0, h, 1.1, 8.0)
            box(stone, x0 - 1.0, x0, 4.0, h, -1.1, 1.1)
    box(stone, -67.0, -66.0, 0.0, 8.0, -9.0, 9.0)       # the sanctuary's back wall
    # Walls closing the hall's back corners outside the vestibules.
    box(stone, -39.5, -38.0, 0.0, 11.0, -12.0, -9.0)
    box(stone, -39.5, -38.0, 0.0, 11.0, 9.0, 12.0)
    # The enclosure wall around the temple house, meeting the pylon's ends.
    box(dark, -76.0, -5.0, 0.0, 6.0, -18.0, -16.5)
    box(dark, -76.0, -5.0, 0.0, 6.0, 16.5, 18.0)
    box(dark, -76.0, -74.5, 0.0, 6.0, -16.5, 16.5)


def kalabsha_height(x, z):
    """The promontory: a flat terrace about the temple at y = 0, falling to the lake in the
    east (local frame rotated with the temple is not needed: the slope is gentle), desert
    hills rising to the west. Metres."""
    r = math.hypot(x + 30.0, z)
    plateau = smoothstep(110.0, 260.0, r)
    east = smoothstep(60.0, 260.0, x)          # towards the lake
    west = smoothstep(200.0, 1400.0, -x)       # towards the desert hills
    rolling = 6.0 * math.sin(x / 170.0 + 0.5) * math.cos(z / 210.0 - 0.3) + 3.0 * math.sin(z / 90.0)
    return plateau * (-16.0 * east + 70.0 * west + rolling * (1 - east))


def make_kalabsha(out_dir):
    g = Gltf("kalabsha")
    g.doc["asset"]["generator"] = "welkin apps/demos/heritage/make_heritage.py"
    stone_m = g.material("sandstone", SANDSTONE, 0.0, 0.85)
    dark_m = g.material("sandstone_weathered", SANDSTONE_DARK, 0.0, 0.9)
    ground_m = g.material("ground", (1.0, 1.0, 1.0), 0.0, 0.95)
    water_m = g.material("lake", WATER, 0.0, 0.08)
    stone, dark = MeshBuilder(), MeshBuilder()
    kalabsha_temple(stone, dark)
    mesh = g.mesh("kalabsha_temple", [stone.primitive(g, stone_m), dark.primitive(g, dark_m)])
    g.node("kalabsha_temple", mesh, (0.0, 0.0, 0.0), 90.0 - KALABSHA_AXIS_AZIMUTH_DEG)

    def colour(x, y, z):
        # The promontory is dark granite with drifts of orange sand; granite down to the water.
        f = 0.5 + 0.5 * math.sin(0.021 * x + 0.017 * z) * math.sin(0.013 * x - 0.029 * z + 1.0)
        sand = smoothstep(0.35, 0.75, f) * (1.0 - smoothstep(-2.0, -10.0, y))
        return mix(GRANITE, DESERT, 0.25 + 0.75 * sand)

    ground(g, "promontory", 1500.0, 49, kalabsha_height, colour, ground_m)
    flat(g, "lake", 3000.0, -12.0, water_m)
    g.write(out_dir)


# ---------------------------------------------------------------- Kiti

def kiti_church(stone, plaster):
    """Local frame: +x towards the apse, the crossing's centre at the origin. The church is
    12 m x 10 m inside its walls (x in [-6, 6], z in [-5, 5]), walls 0.8 m thick and 5.5 m
    high, a 2.4 m radius apse, the dome 2.5 m in radius on a drum; a narthex to the west."""
    h = 5.5
    t = 0.8
    # The long (north and south) walls with two windows each (gaps 1.2 m high at 2.6 m).
    for s in (-1, 1):
        z0, z1 = (5.0, 5.0 + t) if s > 0 else (-5.0 - t, -5.0)
        for xa, xb in ((-6.8, -4.2), (-2.8, 1.8), (3.2, 6.8)):
            box(stone, xa, xb, 0.0, h, z0, z1)
        for xa, xb in ((-4.2, -2.8), (1.8, 3.2)):
            box(stone, xa, xb, 0.0, 2.6, z0, z1)
            box(stone, xa, xb, 3.8, h, z0, z1)
    # The west wall with its door (1.6 m wide, 2.8 m high).
    box(stone, -6.8, -6.0, 0.0, h, -5.8, -0.8)
    box(stone, -6.8, -6.0, 0.0, h, 0.8, 5.8)
    box(stone, -6.8, -6.0, 2.8, h, -0.8, 0.8)
    # The east wall, open in the middle to the apse.
    box(stone, 6.0, 6.8, 0.0, h, -5.8, -2.4)
    box(stone, 6.0, 6.8, 0.0, h, 2.4, 5.8)
    box(stone, 6.0, 6.8, 4.6, h, -2.4, 2.4)
    # The apse: a half cylinder of wall east of x = 6.8 with a window, its (flattened) half dome
    # from 4.6 m.
    curved_wall(stone, 6.8, 0.0, 2.4, 3.1, -0.5 * math.pi, -0.12, 0.0, 4.6, 6)
    curved_wall(stone, 6.8, 0.0, 2.4, 3.1, 0.12, 0.5 * math.pi, 0.0, 4.6, 6)
    curved_wall(stone, 6.8, 0.0, 2.4, 3.1, -0.12, 0.12, 0.0, 1.8, 1)
    curved_wall(stone, 6.8, 0.0, 2.4, 3.1, -0.12, 0.12, 3.4, 4.6, 1)
    dome(plaster, 6.8, 4.6, 0.0, 3.1, -0.5 * math.pi, 0.5 * math.pi, 10, 5, 0.5)
    # Four piers carrying the crossing's arches and its dome.
    for px in (-2.5, 2.5):
        for pz in (-2.5, 2.5):
            box(stone, px - 0.5, px + 0.5, 0.0, h, pz - 0.5, pz + 0.5)
    # Barrel vaults over the four arms (radius 2.5, springing at the walls' top), the corner
    # bays under flat roofs, the vaults' gable ends closed.
    r = 2.5
    barrel_vault(plaster, "x", -6.8, -2.5, 0.0, h, r)
    barrel_vault(plaster, "x", 2.5, 6.8, 0.0, h, r)
    barrel_vault(plaster, "z", -5.8, -2.5, 0.0, h, r)
    barrel_vault(plaster, "z", 2.5, 5.8, 0.0, h, r)
    vault_end(stone, "x", -6.8, 0.0, h, r)
    vault_end(stone, "x", 6.8, 0.0, h, r)
    vault_end(stone, "z", -5.8, 0.0, h, r)
    vault_end(stone, "z", 5.8, 0.0, h, r)
    for sx in (-1, 1):
        for sz in (-1, 1):
            xa, xb = sorted((2.5 * sx, 6.8 * sx))
            za, zb = sorted((2.5 * sz, 5.8 * sz))
            box(plaster, xa, xb, h, h + 0.5, za, zb)
    # The crossing: the arches' spandrels up to the crowns, pendentives (a ring from the
    # crossing's square to the drum's circle, eight flat pieces) and the drum on top (twelve wall
    # segments, every other one up to the window sills only).
    y_drum = h + r
    for xs in (-2.5, 2.5):
        spandrel(plaster, "x", xs, 0.0, h, r, y_drum)
        spandrel(plaster, "z", xs, 0.0, h, r, y_drum)
    for i in range(8):
        a0, a1 = 2 * math.pi * i / 8, 2 * math.pi * (i + 1) / 8
        sq = lambda a: 2.5 / max(abs(math.cos(a)), abs(math.sin(a)))
        ring = lambda y: [(2.0 * math.cos(a0), y, 2.0 * math.sin(a0)), (sq(a0) * math.cos(a0), y, sq(a0) * math.sin(a0)),
                          (sq(a1) * math.cos(a1), y, sq(a1) * math.sin(a1)), (2.0 * math.cos(a1), y, 2.0 * math.sin(a1))]
        prism(plaster, ring(y_drum - 0.3), ring(y_drum + 0.3), True)
    n = 12
    for i in range(n):
        a0, a1 = 2 * math.pi * i / n, 2 * math.pi * (i + 1) / n
        top = y_drum + 2.4 if i % 2 == 0 else y_drum + 0.9
        curved_wall(stone, 0.0, 0.0, 2.0, 2.5, a0, a1, y_drum + 0.3, top, 1)
        if i % 2 == 1:
            curved_wall(stone, 0.0, 0.0, 2.0, 2.5, a0, a1, y_drum + 2.0, y_drum + 2.4, 1)
    dome(plaster, 0.0, y_drum + 2.4, 0.0, 2.5, 0.0, 2 * math.pi, 16, 6)
    # The chapel of Saints Kosmas and Damian (12th century) along the north side: a lower
    # barrel-vaulted hall sharing the church's north wall, its door to the west.
    cz, hc, rc = -8.0, 4.0, 2.2
    box(stone, -6.8, 5.0, 0.0, hc, -10.9, -10.2)                 # north wall
    box(stone, 4.3, 5.0, 0.0, hc, -10.2, -5.8)                   # east wall
    box(stone, -6.8, -6.1, 0.0, hc, -10.2, -8.7)                 # west wall with its door
    box(stone, -6.8, -6.1, 0.0, hc, -7.3, -5.8)
    box(stone, -6.8, -6.1, 2.4, hc, -8.7, -7.3)
    barrel_vault(plaster, "x", -6.8, 5.0, cz, hc, rc + 0.5)
    vault_end(stone, "x", -6.8, cz, hc, rc + 0.5)
    vault_end(stone, "x", 5.0, cz, hc, rc + 0.5)
    # The narthex (a later, lower hall) west of the church with a pitched roof and a door.
    x0, x1 = -11.0, -6.8
    box(stone, x0, x1, 0.0, 4.0, -5.8, -5.0)
    box(stone, x0, x1, 0.0, 4.0, 5.0, 5.8)
    box(stone, x0 - 0.8, x0, 0.0, 4.0, -5.8, -0.9)
    box(stone, x0 - 0.8, x0, 0.0, 4.0, 0.9, 5.8)
    box(stone, x0 - 0.8, x0, 2.6, 4.0, -0.9, 0.9)
    for s in (-1, 1):
        face(plaster, [(x0 - 1.0, 4.0, 6.1 * s), (x1, 4.0, 6.1 * s), (x1, 5.4, 0.0), (x0 - 1.0, 5.4, 0.0)], (x0, 0.0, 0.0))
        face(plaster, [(x0 - 1.0, 3.99, 6.1 * s), (x1, 3.99, 6.1 * s), (x1, 5.39, 0.0), (x0 - 1.0, 5.39, 0.0)], (x0, 10.0, 0.0))
    for xe in (x0 - 0.8, x1):
        both(stone, [(xe, 4.0, -5.8), (xe, 4.0, 5.8), (xe, 5.3, 0.0)])


def kiti_height(x, z):
    """Gently sloping fields about the village, the sea (not modelled) to the south. Metres."""
    r = math.hypot(x, z)
    return smoothstep(60.0, 400.0, r) * (4.0 * math.sin(x / 230.0) * math.cos(z / 190.0 + 0.4) - 0.012 * (z - 60.0))


def make_kiti(out_dir):
    g = Gltf("kiti")
    g.doc["asset"]["generator"] = "welkin apps/demos/heritage/make_heritage.py"
    stone_m = g.material("limestone", LIMESTONE, 0.0, 0.85)
    plaster_m = g.material("lime_plaster", PLASTER, 0.0, 0.8)
    ground_m = g.material("ground", (1.0, 1.0, 1.0), 0.0, 0.95)
    stone, plaster = MeshBuilder(), MeshBuilder()
    kiti_church(stone, plaster)
    mesh = g.mesh("kiti_church", [stone.primitive(g, stone_m), plaster.primitive(g, plaster_m)])
    g.node("kiti_church", mesh, (0.0, 0.0, 0.0), 90.0 - KITI_APSE_AZIMUTH_DEG)

    def colour(x, y, z):
        if abs(x) < 16.0 and abs(z) < 12.0:
            return (0.30, 0.27, 0.22)  # the paved churchyard
        f = smoothstep(-0.3, 0.8, math.sin(0.03 * x + 0.02 * z) + 0.6 * math.sin(-0.05 * x + 0.04 * z + 1.0))
        return mix(EARTH, SCRUB, f)

    ground(g, "fields", 1500.0, 49, kiti_height, colour, ground_m)
    g.write(out_dir)


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else HERE
    if len(sys.argv) > 2 or not os.path.isdir(out_dir):
        sys.exit("make_heritage.py: OUT_DIR must be an existing directory (usage: make_heritage.py [OUT_DIR])")
    make_kalabsha(out_dir)
    make_kiti(out_dir)


if __name__ == "__main__":
    main()
