#!/usr/bin/env python3
"""Writes the host example's glTF 2.0 assets (metres, Y-up: x east, y up, -z north).

    python3 examples/host/assets/make_assets.py [OUT_DIR]      # default: this script's folder

  terrain.gltf + terrain.bin      a 6 km x 6 km heightfield: a flat village floor at the origin,
                                  a valley running north-south, gentle hills rising towards the
                                  edges; per-vertex normals; base colour by slope (dry fields and
                                  scrub, limestone on slopes; COLOR_0, linear)
  buildings.gltf + buildings.bin  houses with pitched roofs and square towers in sandstone,
                                  terracotta roofs; one named node per building ("house_n1",
                                  "keep_far" ...) standing on the terrain
  spheres.gltf + spheres.bin      a row of ten spheres (radius 1.4 m) 30 m west of the camera:
                                  five white dielectrics then five gold metals, each from rough to
                                  smooth (roughness 1.0, 0.75, 0.5, 0.25, 0.05; metallic-roughness)

Plain python3 (struct, json, math): the same script writes the same bytes every time.
"""
import json
import math
import os
import struct
import sys

# ---------------------------------------------------------------- terrain height (metres)

TERRAIN_HALF = 3000.0  # the heightfield covers [-3000, 3000] m in x and z
TERRAIN_N = 161        # vertices per side: 37.5 m spacing


def smoothstep(e0, e1, x):
    t = min(max((x - e0) / (e1 - e0), 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def height(x, z):
    """Terrain height at (x, z), metres: 0 on the village floor (within ~350 m of the origin)."""
    r = math.hypot(x, z)
    # Hills rising towards the edges of the map (a basin about the village), with a ridge to the
    # west on which the far keep stands.
    rim = 170.0 * smoothstep(900.0, 2900.0, r)
    ridge = 70.0 * math.exp(-((x + 2400.0) ** 2) / (2 * 420.0 ** 2)) * math.exp(-((z + 150.0) ** 2) / (2 * 700.0 ** 2))
    rolling = (14.0 * math.sin(x / 410.0 + 0.7) * math.cos(z / 530.0 - 0.4)
               + 7.0 * math.sin(x / 170.0 - 1.3) * math.sin(z / 230.0 + 2.1))
    # A valley running north-south east of the village, 35 m deep.
    valley = -35.0 * math.exp(-((x - 900.0) ** 2) / (2 * 160.0 ** 2)) * smoothstep(0.0, 600.0, r)
    h = rim + ridge + rolling + valley
    # The village floor: flat within 350 m, blended over the next 400 m.
    return h * smoothstep(350.0, 750.0, r)


def terrain_normal(x, z, e=1.0):
    hx = (height(x + e, z) - height(x - e, z)) / (2 * e)
    hz = (height(x, z + e) - height(x, z - e)) / (2 * e)
    n = (-hx, 1.0, -hz)
    l = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
    return (n[0] / l, n[1] / l, n[2] / l)


# ---------------------------------------------------------------- glTF writer


class Gltf:
    """Collects buffer views, accessors, meshes and nodes into one .gltf with one .bin."""

    def __init__(self, name):
        self.name = name
        self.bin = bytearray()
        self.doc = {
            "asset": {"version": "2.0", "generator": "welkin examples/host/assets/make_assets.py"},
            "scene": 0,
            "scenes": [{"name": name, "nodes": []}],
            "nodes": [], "meshes": [], "materials": [], "accessors": [], "bufferViews": [],
            "buffers": [],
        }

    def _view(self, data, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data), "target": target}
        self.bin += data
        self.doc["bufferViews"].append(view)
        return len(self.doc["bufferViews"]) - 1

    def vec3(self, values, with_bounds=False):
        data = b"".join(struct.pack("<3f", *v) for v in values)
        acc = {"bufferView": self._view(data, 34962), "componentType": 5126, "count": len(values), "type": "VEC3"}
        if with_bounds:
            # Bounds of the float32 values as stored.
            stored = [struct.unpack("<3f", struct.pack("<3f", *v)) for v in values]
            acc["min"] = [min(v[i] for v in stored) for i in range(3)]
            acc["max"] = [max(v[i] for v in stored) for i in range(3)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def color_u8(self, values):
        """COLOR_0 as normalised unsigned bytes, RGBA (alpha 1)."""
        data = b"".join(struct.pack("<4B", *[max(0, min(255, round(c * 255))) for c in v], 255) for v in values)
        self.doc["accessors"].append({"bufferView": self._view(data, 34962), "componentType": 5121,
                                      "normalized": True, "count": len(values), "type": "VEC4"})
        return len(self.doc["accessors"]) - 1

    def indices(self, values):
        assert max(values) < 65536
        data = struct.pack("<%dH" % len(values), *values)
        self.doc["accessors"].append({"bufferView": self._view(data, 34963), "componentType": 5123,
                                      "count": len(values), "type": "SCALAR"})
        return len(self.doc["accessors"]) - 1

    def material(self, name, base, metallic, roughness):
        self.doc["materials"].append({"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": [base[0], base[1], base[2], 1.0],
            "metallicFactor": metallic, "roughnessFactor": roughness}})
        return len(self.doc["materials"]) - 1

    def mesh(self, name, primitives):
        self.doc["meshes"].append({"name": name, "primitives": primitives})
        return len(self.doc["meshes"]) - 1

    def node(self, name, mesh, translation=(0, 0, 0), yaw_deg=0.0):
        node = {"name": name, "mesh": mesh}
        if any(translation):
            node["translation"] = [round(t, 4) + 0.0 for t in translation]
        if yaw_deg:
            h = math.radians(yaw_deg) / 2  # rotation about +y, glTF quaternion (x, y, z, w)
            node["rotation"] = [0.0, round(math.sin(h), 8), 0.0, round(math.cos(h), 8)]
        self.doc["nodes"].append(node)
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)

    def write(self, out_dir):
        self.doc["buffers"].append({"uri": self.name + ".bin", "byteLength": len(self.bin)})
        with open(os.path.join(out_dir, self.name + ".bin.tmp"), "wb") as f:
            f.write(self.bin)
        with open(os.path.join(out_dir, self.name + ".gltf.tmp"), "w") as f:
            json.dump(self.doc, f, indent=1, sort_keys=True)
            f.write("\n")
        for ext in (".bin", ".gltf"):
            os.replace(os.path.join(out_dir, self.name + ext + ".tmp"), os.path.join(out_dir, self.name + ext))


# ---------------------------------------------------------------- terrain

DRY_GRASS = (0.17, 0.13, 0.065)   # linear albedo of sun-dried fields (a Maltese summer)
SCRUB = (0.065, 0.085, 0.035)     # garrigue and green scrub
LIMESTONE = (0.42, 0.38, 0.30)    # weathered globigerina limestone


def field_pattern(x, z):
    """Patches of dry fields and scrub in [0, 1] (1: scrub): sums of rotated sinusoids, smooth
    over ~100 m, so the ground reads as fields from the camera and is the same on every run."""
    a = math.sin(0.013 * x + 0.021 * z + 1.7) + math.sin(-0.019 * x + 0.011 * z + 0.4)
    b = math.sin(0.047 * x - 0.031 * z + 2.9) * 0.6 + math.sin(0.029 * x + 0.053 * z - 1.1) * 0.6
    return smoothstep(-0.4, 0.9, 0.6 * a + 0.5 * b)


def make_terrain(out_dir):
    g = Gltf("terrain")
    n = TERRAIN_N
    pos, nor, col = [], [], []
    for j in range(n):
        z = -TERRAIN_HALF + 2 * TERRAIN_HALF * j / (n - 1)
        for i in range(n):
            x = -TERRAIN_HALF + 2 * TERRAIN_HALF * i / (n - 1)
            pos.append((x, height(x, z), z))
            nn = terrain_normal(x, z)
            nor.append(nn)
            # Slope from the normal: grass up to ~12 degrees, rock above ~22 degrees.
            slope = math.degrees(math.acos(min(1.0, nn[1])))
            t = smoothstep(12.0, 22.0, slope)
            f = field_pattern(x, z)
            grass = tuple(DRY_GRASS[c] * (1 - f) + SCRUB[c] * f for c in range(3))
            col.append(tuple(grass[c] * (1 - t) + LIMESTONE[c] * t for c in range(3)))
    idx = []
    for j in range(n - 1):
        for i in range(n - 1):
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i, (j + 1) * n + i + 1
            idx += [a, c, b, b, c, d]  # counter-clockwise seen from above (+y)
    mat = g.material("terrain", (1.0, 1.0, 1.0), 0.0, 0.92)
    prim = {"attributes": {"POSITION": g.vec3(pos, True), "NORMAL": g.vec3(nor), "COLOR_0": g.color_u8(col)},
            "indices": g.indices(idx), "material": mat, "mode": 4}
    g.node("terrain", g.mesh("terrain", [prim]))
    g.write(out_dir)


# ---------------------------------------------------------------- buildings


class MeshBuilder:
    """Flat-shaded triangles: each polygon gets its own vertices and its face normal."""

    def __init__(self):
        self.pos, self.nor, self.idx = [], [], []

    def polygon(self, pts):
        """A planar convex polygon, counter-clockwise seen from outside."""
        ax, ay, az = (pts[1][k] - pts[0][k] for k in range(3))
        bx, by, bz = (pts[2][k] - pts[0][k] for k in range(3))
        nx, ny, nz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
        l = math.sqrt(nx * nx + ny * ny + nz * nz)
        base = len(self.pos)
        for p in pts:
            self.pos.append(p)
            self.nor.append((nx / l, ny / l, nz / l))
        for k in range(1, len(pts) - 1):
            self.idx += [base, base + k, base + k + 1]

    def primitive(self, g, material):
        return {"attributes": {"POSITION": g.vec3(self.pos, True), "NORMAL": g.vec3(self.nor)},
                "indices": g.indices(self.idx), "material": material, "mode": 4}


def house(walls, roof, w, d, h, ridge, base=-2.0):
    """A house w (x) by d (z), walls h high above y = 0 (down to `base` below), a gable roof
    whose ridge runs along x, `ridge` above the eaves, overhanging 0.4 m."""
    x0, x1, z0, z1 = -w / 2, w / 2, -d / 2, d / 2
    walls.polygon([(x0, base, z1), (x1, base, z1), (x1, h, z1), (x0, h, z1)])          # south (+z)
    walls.polygon([(x1, base, z0), (x0, base, z0), (x0, h, z0), (x1, h, z0)])          # north (-z)
    walls.polygon([(x1, base, z1), (x1, base, z0), (x1, h, z0), (x1, h + ridge, 0.0), (x1, h, z1)])  # east gable
    walls.polygon([(x0, base, z0), (x0, base, z1), (x0, h, z1), (x0, h + ridge, 0.0), (x0, h, z0)])  # west gable
    o = 0.4
    s = ridge / (d / 2)  # roof slope: the overhang drops by o * s
    ex0, ex1 = x0 - o, x1 + o
    roof.polygon([(ex0, h - o * s, z1 + o), (ex1, h - o * s, z1 + o), (ex1, h + ridge, 0.0), (ex0, h + ridge, 0.0)])  # south slope
    roof.polygon([(ex1, h - o * s, z0 - o), (ex0, h - o * s, z0 - o), (ex0, h + ridge, 0.0), (ex1, h + ridge, 0.0)])  # north slope


def tower(walls, roof, w, h, spire, base=-2.0):
    """A square tower w by w, h high, a pyramid roof `spire` high."""
    a = w / 2
    c = [(-a, a), (a, a), (a, -a), (-a, -a)]  # (x, z) counter-clockwise seen from above
    for k in range(4):
        (xa, za), (xb, zb) = c[k], c[(k + 1) % 4]
        walls.polygon([(xa, base, za), (xb, base, zb), (xb, h, zb), (xa, h, za)])
        roof.polygon([(xa, h, za), (xb, h, zb), (0.0, h + spire, 0.0)])


SANDSTONE = (0.50, 0.36, 0.20)    # Maltese globigerina limestone ("sandstone"), linear albedo
TERRACOTTA = (0.36, 0.12, 0.06)

# name, kind, x, z, yaw (degrees), dimensions. The camera's default place is (0, 8, 0) looking
# west (-x): houses north of the line of sight (z < 0) show their sunny south walls at noon,
# houses south of it (z > 0) their shaded north walls; "keep_far" stands 2.4 km west on a ridge.
BUILDINGS = [
    ("house_n1", "house_a", -95.0, -42.0, 0.0),
    ("house_s1", "house_a", -105.0, 46.0, 0.0),
    ("house_n2", "house_b", -160.0, -75.0, 0.0),
    ("house_s2", "house_b", -175.0, 90.0, 0.0),
    ("tower_n", "tower_a", -240.0, -30.0, 0.0),
    ("house_n3", "house_a", -300.0, -130.0, 0.0),
    ("house_s3", "house_b", -320.0, 150.0, 0.0),
    ("house_w1", "house_a", -420.0, 20.0, 0.0),
    ("tower_s", "tower_a", -460.0, 110.0, 0.0),
    ("keep_far", "keep", -2400.0, -150.0, 0.0),
]


def make_buildings(out_dir):
    g = Gltf("buildings")
    walls_m = g.material("sandstone", SANDSTONE, 0.0, 0.85)
    roof_m = g.material("terracotta", TERRACOTTA, 0.0, 0.7)
    shapes = {
        "house_a": lambda w, r: house(w, r, 12.0, 8.0, 6.0, 3.0),
        "house_b": lambda w, r: house(w, r, 16.0, 10.0, 7.5, 3.5),
        "tower_a": lambda w, r: tower(w, r, 7.0, 22.0, 6.0),
        "keep": lambda w, r: tower(w, r, 30.0, 55.0, 14.0, base=-8.0),
    }
    meshes = {}
    for kind, build in shapes.items():
        walls, roof = MeshBuilder(), MeshBuilder()
        build(walls, roof)
        meshes[kind] = g.mesh(kind, [walls.primitive(g, walls_m), roof.primitive(g, roof_m)])
    for name, kind, x, z, yaw in BUILDINGS:
        # Stand on the lowest ground under the footprint's centre and corners (the walls reach
        # below y = 0, so no wall floats above a slope).
        r = 16.0
        y = min(height(x + dx, z + dz) for dx in (-r, 0.0, r) for dz in (-r, 0.0, r))
        g.node(name, meshes[kind], (x, y, z), yaw)
    g.write(out_dir)


# ---------------------------------------------------------------- spheres

SPHERE_R = 1.4
ROUGHNESS = [1.0, 0.75, 0.5, 0.25, 0.05]


def make_spheres(out_dir):
    g = Gltf("spheres")
    seg, rings = 48, 24
    pos, nor, idx = [], [], []
    for j in range(rings + 1):
        th = math.pi * j / rings
        for i in range(seg + 1):
            ph = 2 * math.pi * i / seg
            n = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            nor.append(n)
            pos.append(tuple(SPHERE_R * c for c in n))
    for j in range(rings):
        for i in range(seg):
            a, b = j * (seg + 1) + i, (j + 1) * (seg + 1) + i
            idx += [a, b, a + 1, a + 1, b, b + 1]
    attrs = {"POSITION": g.vec3(pos, True), "NORMAL": g.vec3(nor)}
    ind = g.indices(idx)
    # One row across the view, 30 m west of the camera: five dielectrics (white) on the left
    # (south), then five metals (gold) on the right (north), each from rough to smooth.
    rows = [("dielectric", (0.80, 0.80, 0.80), 0.0),   # white plaster-like dielectric
            ("metal", (1.00, 0.71, 0.29), 1.0)]        # gold: its F0, linear sRGB
    k = 0
    for kind, base, metallic in rows:
        for j, rough in enumerate(ROUGHNESS):
            m = g.material("%s_r%.2f" % (kind, rough), base, metallic, rough)
            mesh = g.mesh("sphere_%s_r%.2f" % (kind, rough), [{"attributes": attrs, "indices": ind, "material": m, "mode": 4}])
            z = 18.0 - 4.0 * k  # from south (left when looking west) to north
            g.node("sphere_%s_%d" % (kind, j), mesh, (-30.0, SPHERE_R, z))
            k += 1
    g.write(out_dir)


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    if len(sys.argv) > 2 or not os.path.isdir(out_dir):
        sys.exit("make_assets.py: OUT_DIR must be an existing directory (usage: make_assets.py [OUT_DIR])")
    make_terrain(out_dir)
    make_buildings(out_dir)
    make_spheres(out_dir)


if __name__ == "__main__":
    main()
