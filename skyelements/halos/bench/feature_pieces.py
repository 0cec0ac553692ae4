#!/usr/bin/env python3
# The share of the halo pass's drawn pixels that a halo feature crosses, piece by piece, on the
# geometry of `welkin bench halos` (perspective, 100 deg vertical, looking south 30 deg up, the Sun
# south 20 deg up): the least share an interpolating display must still fetch per pixel if every
# piece no feature crosses were drawn from its corners (skyelements/halos/README.md, "What any
# route costs at least"). A piece fetches if any of its 9 x 9 directions above the horizon lies on
# a feature: the 22 and 46 deg halos' edges (20.5-25 and 44.5-49 deg from the light), the parhelic
# circle (within 1.5 deg of the light's elevation), the circumzenithal arc (60-72 deg up within 50
# deg of the light's azimuth), the upper tangent arc (20.5-32 deg from the light within 30 deg of
# its azimuth, above 30 deg up), the light's own 3 deg. Pieces wholly below the horizon are not drawn.
# Usage: python3 skyelements/halos/bench/feature_pieces.py
import math


def share(W, H, C, quarters):
    vf, az0, alt0, h = math.radians(100), math.pi, math.radians(30), math.radians(20)
    f = H / 2 / math.tan(vf / 2)  # focal length, pixels
    fw = (math.sin(az0) * math.cos(alt0), math.cos(az0) * math.cos(alt0), math.sin(alt0))  # east, north, up
    rt = (math.cos(az0), -math.sin(az0), 0.0)
    up = (rt[1] * fw[2] - rt[2] * fw[1], rt[2] * fw[0] - rt[0] * fw[2], rt[0] * fw[1] - rt[1] * fw[0])
    L = (math.sin(az0) * math.cos(h), math.cos(az0) * math.cos(h), math.sin(h))

    def direction(px, py):
        x, y = (px - W / 2) / f, (H / 2 - py) / f
        d = [fw[i] + x * rt[i] + y * up[i] for i in range(3)]
        n = math.sqrt(sum(c * c for c in d))
        return [c / n for c in d]

    def crossed(px0, py0, side):  # None: below the horizon
        th, el, daz = [], [], []
        for j in range(9):
            for i in range(9):
                d = direction(px0 + side * i / 8, py0 + side * j / 8)
                if d[2] < 0:
                    continue
                th.append(math.degrees(math.acos(max(-1.0, min(1.0, sum(d[k] * L[k] for k in range(3)))))))
                el.append(math.degrees(math.asin(d[2])))
                daz.append(abs(math.degrees(math.atan2(d[0], d[1])) - 180))
        if not th:
            return None
        meets = lambda lo, hi, v: min(v) <= hi and max(v) >= lo
        return (meets(20.5, 25, th) or meets(44.5, 49, th) or meets(18.5, 21.5, el) or (meets(60, 72, el) and min(daz) < 50)
                or (meets(20.5, 32, th) and min(daz) < 30 and max(el) > 30) or min(th) < 3)

    fetch = drawn = 0
    for cy in range(0, H, C):
        for cx in range(0, W, C):
            r = crossed(cx, cy, C)
            if r is None:
                continue
            drawn += min(C, W - cx) * min(C, H - cy)
            if r and quarters:
                for q in range(4):
                    qx, qy = cx + (q & 1) * C // 2, cy + (q >> 1) * C // 2
                    if qx < W and qy < H and crossed(qx, qy, C // 2):
                        fetch += min(C // 2, W - qx) * min(C // 2, H - qy)
            elif r:
                fetch += min(C, W - cx) * min(C, H - cy)
    return fetch / drawn


for W, H in ((1280, 720), (512, 256)):
    print(f"{W}x{H}: 64-pixel pieces {share(W, H, 64, False):.2f}, 32-pixel {share(W, H, 32, False):.2f}, "
          f"64 with crossed ones split into quarters {share(W, H, 64, True):.2f} of the drawn pixels fetch")
