#!/usr/bin/env python3
# Refits the eclipse's multiple-scattering weight (atm_eclMsWeight(), atmosphere.shared.glsl) and
# the kernel's length (cpu::eclipseMsLength()) on a dump of `welkin bench eclipse` (docs/eclipse.md,
# "The ring of directions"). Plain Python (no numpy): Nelder-Mead on the least squares of
# ln(model / reference) + 0.5 ln^4, totality weighted 1, the partial phases 0.3.
#
# The dump, one run per place and air (the model is linear in its weight w, and the dump holds it
# at w = 0 and at w = 1 for each kernel length of --dump-lengths):
#   for pl in burgos reykjavik luxor; do for hz in false true; do
#     build/bin/welkin bench eclipse --cost false --coarse true --place $pl --hazy $hz \
#       --dump dump.csv --dump-lengths 18,24,30,36,43,52,62; done; done
#   skyelements/sky/bench/fit_eclipse_weight.py dump.csv
# (The dump's own w = 1 column is at the built cpu::eclipseMsLength(); the fit interpolates the
# lengths' columns linearly in ln L, which errs by 5-10 % at Luxor where the model is steep in L:
# check a fit with `welkin bench eclipse --ring true` after building it.)
import csv, math, sys

LS = [18, 24, 30, 36, 43, 52, 62]  # km: --dump-lengths
KEYS = ['rate', 'fmu', 'spow', 'hpow', 'elong', 'ring', 'gain', 'gainH', 'gainMu', 'gainPow', 'L0', 'Lpow']
# The shipped constants (atmosphere.shared.glsl's literals, sky_model.hpp's kEclipse*).
START = dict(rate=23.6, fmu=0.47, spow=0.85, hpow=0.40, elong=2.26, ring=0.50, gain=0.88, gainH=-0.23, gainMu=0.34, gainPow=2.1,
             L0=31.5, Lpow=0.07)
RING_G = 0.4          # kEclipseHazeRingG (kept)
FORWARD = {'renderer': 0.187, 'hazy': 0.142}  # the delta-M forward fractions (g 0.8, 0.75)
LAMBDA = 0.5


def load(path):
    rows = []
    for r in csv.reader(open(path)):
        d = dict(place=r[0], atm=r[1], phase=r[2], daz=float(r[4]), alt=float(r[5]), ref=float(r[6]), a0=float(r[7]), a1=float(r[8]),
                 muS=float(r[12]), nu=float(r[13]), sM=float(r[15]), sR=float(r[16]), umbra=float(r[21]), fromAxis=float(r[22]),
                 a1L=[float(x) for x in r[23:23 + len(LS)]])
        d['mu'] = math.sin(math.radians(d['alt']))
        rows.append(d)
    return rows


def cos_ring(mu, muS, nu):
    sm, ss = math.sqrt(max(1 - mu * mu, 0)), math.sqrt(max(1 - muS * muS, 0))
    ca = max(-1.0, min(1.0, (nu - mu * muS) / (sm * ss))) if sm * ss > 1e-9 else 1.0
    return sm * math.sqrt(max(1 - ca * ca, 0))


def hg(c, g):
    d = max(1 + g * g - 2 * g * c, 1e-12)
    return (1 - g * g) / (d * math.sqrt(d))


def weight(d, P):  # atm_eclMsWeight()
    nu, mu, muS = d['nu'], d['mu'], d['muS']
    F = min(1.0, FORWARD.get(d['atm'], 0.187) * d['sM'] / (d['sM'] + d['sR']) / 0.16)
    H = max(0.0, min(1.0, (d['sM'] / 7.5e-5 - 1.1) / 2.9))
    cr = cos_ring(mu, muS, nu)
    X = 1 / max(muS, 0.05)
    G = 1 - math.exp(-P['rate'] * (X - 1))
    E = (X - 1) ** 2 / ((X - 1) ** 2 + P['elong'] ** 2)
    w = 1.0
    if nu > 0:
        s = min(math.sqrt(max(1 - nu * nu, 0)), math.sqrt(cr * cr + (P['fmu'] * mu * X) ** 2))
        s = max(s, 1e-6) ** (P['spow'] * (1 + P['hpow'] * H))
        w = max(1 - max(F, H) * G * (1 - s), 0)
    R = P['ring'] * (1 + (0.5 * (hg(cr, RING_G) + hg(-cr, RING_G)) - 1) * E)
    x = max(mu, 0) / max(P['gainMu'], 1e-3)
    gain = 1 + P['gain'] * (1 + P['gainH'] * H) * (x * math.exp(1 - x)) ** max(P['gainPow'], 0.2)
    return w * (1 + (R - 1) * H) * gain


def length(d, P):  # cpu::eclipseMsLength(), km
    return P['L0'] * (max(d['umbra'] - d['fromAxis'], 1e3) / 50e3) ** P['Lpow']


def a1_at(d, L):
    xs, lnL = [math.log(l) for l in LS], math.log(L)
    i = 0 if lnL <= xs[0] else len(xs) - 2 if lnL >= xs[-1] else max(k for k in range(len(xs) - 1) if xs[k] <= lnL)
    t = (lnL - xs[i]) / (xs[i + 1] - xs[i])
    return d['a1L'][i] * (1 - t) + d['a1L'][i + 1] * t


def model(d, P):
    return max(d['a0'] + weight(d, P) * (a1_at(d, length(d, P)) - d['a0']), 1e-30)


def cost(P, rows):
    s = n = 0.0
    for d in rows:
        e = math.log(model(d, P) / d['ref'])
        k = 1.0 if d['phase'] == 'totality' else 0.3
        s += k * (e * e + LAMBDA * e ** 4)
        n += k
    return s / n


def nelder_mead(f, x0, steps, iters):
    n = len(x0)
    pts = [list(x0)] + [[x0[j] + (steps[i] if j == i else 0) for j in range(n)] for i in range(n)]
    vals = [f(p) for p in pts]
    for _ in range(iters):
        order = sorted(range(n + 1), key=lambda i: vals[i])
        pts, vals = [pts[i] for i in order], [vals[i] for i in order]
        c = [sum(p[j] for p in pts[:-1]) / n for j in range(n)]
        xr = [2 * c[j] - pts[-1][j] for j in range(n)]
        fr = f(xr)
        if fr < vals[0]:
            xe = [3 * c[j] - 2 * pts[-1][j] for j in range(n)]
            fe = f(xe)
            pts[-1], vals[-1] = (xe, fe) if fe < fr else (xr, fr)
        elif fr < vals[-2]:
            pts[-1], vals[-1] = xr, fr
        else:
            xc = [0.5 * (c[j] + pts[-1][j]) for j in range(n)]
            fc = f(xc)
            if fc < vals[-1]:
                pts[-1], vals[-1] = xc, fc
            else:
                for i in range(1, n + 1):
                    pts[i] = [0.5 * (pts[0][j] + pts[i][j]) for j in range(n)]
                    vals[i] = f(pts[i])
    i = min(range(n + 1), key=lambda i: vals[i])
    return pts[i], vals[i]


def summary(P, rows, label):
    print(label)
    for atm in sorted({d['atm'] for d in rows}):
        for pl in ['burgos', 'reykjavik', 'luxor']:
            rs = [model(d, P) / d['ref'] for d in rows if d['atm'] == atm and d['place'] == pl and d['phase'] == 'totality']
            if rs:
                ls = sorted(abs(math.log(r)) for r in rs)
                print(f"  {atm:9s} {pl:10s} {len(rs)} directions: {min(rs):.2f}-{max(rs):.2f}, median factor {math.exp(ls[len(ls) // 2]):.2f}")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: fit_eclipse_weight.py DUMP.csv (welkin bench eclipse --dump ... --dump-lengths 18,24,30,36,43,52,62)")
    rows = load(sys.argv[1])
    bounds = lambda P: dict(P, ring=min(max(P['ring'], 0.1), 1.0), gain=max(P['gain'], 0.0), gainH=max(P['gainH'], -1.0))
    mk = lambda x: bounds(dict(zip(KEYS, x)))
    summary(START, rows, f"the shipped constants: cost {cost(START, rows):.4f} over {len(rows)} points")
    x, c = nelder_mead(lambda x: cost(mk(x), rows), [START[k] for k in KEYS], [0.1 * abs(START[k]) + 0.02 for k in KEYS], 6000)
    P = mk(x)
    summary(P, rows, f"refitted: cost {c:.4f}")
    print({k: round(v, 4) for k, v in P.items()})


if __name__ == '__main__':
    main()
