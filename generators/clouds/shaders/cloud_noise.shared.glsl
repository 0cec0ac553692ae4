// Tileable noise primitives of the cloud noise generators, one source for GLSL and C++
// (welkin/glsl_cpp.hpp): the GPU passes include it through cloud_noise.glsl, the CPU twin
// (cpu:: in cloud_noise.hpp) compiles it in double; the integer hash is the same bit for bit.
// Every function is periodic with period 1 in its normalised coordinate p (a tile), `f` cells per
// tile (integer).
//   uint cn_hash(uint x)                        integer mixer (Wellons' "lowbias32", 2018)
//   real cn_worley(vec3 p, int f, uint seed)    1 - F1 distance (cells), in [0, 1] (Worley 1996)
//   real cn_worleyFbm(vec3 p, int f, uint seed) 0.625 W(f) + 0.25 W(2f) + 0.125 W(4f)
//   real cn_perlin(vec3 p, int f, uint seed)    gradient noise in ~[-1, 1] (Perlin 2002)
//   real cn_perlinFbm(vec3 p, int f, int octaves, uint seed)  in [0, 1]
//   real cn_perlin2(vec2 p, int f, uint seed), cn_perlinFbm2(...)  the 2-D versions
//   vec4 cloudBaseNoise(vec3 p, uint seed), cloudDetailNoise(vec3 p, uint seed),
//        cloudCurlNoise(vec2 p, real e, uint seed)  a texel of each texture at its centre p
//        (the passes cloud_noise_3d.glsl and curl_noise.glsl document the channels)
uint cn_hash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}
uint cn_hash3(ivec3 c, uint seed) { return cn_hash(uint(c.x) + cn_hash(uint(c.y) + cn_hash(uint(c.z) + cn_hash(seed)))); }
real cn_unit(uint h) { return real(h & 0xffffffu) * (1.0 / 16777216.0); }
ivec3 cn_wrap(ivec3 c, int f) { return ((c % f) + f) % f; }

real cn_worley(vec3 p, int f, uint seed) {
    vec3 q = p * real(f);
    ivec3 c0 = ivec3(floor(q));
    real best = 1e9;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                ivec3 c = c0 + ivec3(dx, dy, dz);
                uint h = cn_hash3(cn_wrap(c, f), seed);
                vec3 fp = vec3(c) + vec3(cn_unit(cn_hash(h)), cn_unit(cn_hash(h + 1u)), cn_unit(cn_hash(h + 2u)));
                vec3 d = fp - q;
                best = min(best, dot(d, d));
            }
    return 1.0 - clamp(sqrt(best), 0.0, 1.0);
}

real cn_worleyFbm(vec3 p, int f, uint seed) {
    return 0.625 * cn_worley(p, f, seed) + 0.25 * cn_worley(p, 2 * f, seed + 1u) + 0.125 * cn_worley(p, 4 * f, seed + 2u);
}

real cn_fade(real t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// One of Perlin's 12 edge gradients of the cube (Perlin 2002).
real cn_grad(uint h, vec3 d) {
    int k = int(h % 12u);
    vec3 g = k < 4 ? vec3(k % 2 == 0 ? 1.0 : -1.0, k / 2 == 0 ? 1.0 : -1.0, 0.0)
           : k < 8 ? vec3(k % 2 == 0 ? 1.0 : -1.0, 0.0, (k - 4) / 2 == 0 ? 1.0 : -1.0)
                   : vec3(0.0, k % 2 == 0 ? 1.0 : -1.0, (k - 8) / 2 == 0 ? 1.0 : -1.0);
    return dot(g, d);
}

real cn_perlin(vec3 p, int f, uint seed) {
    vec3 q = p * real(f);
    ivec3 c = ivec3(floor(q));
    vec3 t = q - vec3(c);
    real v[8];
    for (int i = 0; i < 8; ++i) {
        ivec3 o = ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
        v[i] = cn_grad(cn_hash3(cn_wrap(c + o, f), seed), t - vec3(o));
    }
    vec3 u = vec3(cn_fade(t.x), cn_fade(t.y), cn_fade(t.z));
    real x00 = mix(v[0], v[1], u.x), x10 = mix(v[2], v[3], u.x), x01 = mix(v[4], v[5], u.x), x11 = mix(v[6], v[7], u.x);
    return mix(mix(x00, x10, u.y), mix(x01, x11, u.y), u.z);
}

real cn_perlinFbm(vec3 p, int f, int octaves, uint seed) {
    real sum = 0.0, amp = 0.5, norm = 0.0;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * cn_perlin(p, f << o, seed + uint(o));
        norm += amp;
        amp *= 0.5;
    }
    return clamp(0.5 + 0.5 * sum / norm, 0.0, 1.0);
}

real cn_perlin2(vec2 p, int f, uint seed) {
    vec2 q = p * real(f);
    ivec2 c = ivec2(floor(q));
    vec2 t = q - vec2(c);
    real v[4];
    for (int i = 0; i < 4; ++i) {
        ivec2 o = ivec2(i & 1, (i >> 1) & 1);
        ivec2 w = ((c + o) % f + f) % f;
        // 2-D gradients: the 8 directions k pi / 4 of the hash, as unit vectors.
        uint h = cn_hash3(ivec3(w, 0), seed);
        real a = real(h % 8u) * 0.7853981633974483;
        v[i] = dot(vec2(cos(a), sin(a)), t - vec2(o));
    }
    vec2 u = vec2(cn_fade(t.x), cn_fade(t.y));
    return mix(mix(v[0], v[1], u.x), mix(v[2], v[3], u.x), u.y);
}

real cn_perlinFbm2(vec2 p, int f, int octaves, uint seed) {
    real sum = 0.0, amp = 0.5, norm = 0.0;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * cn_perlin2(p, f << o, seed + uint(o));
        norm += amp;
        amp *= 0.5;
    }
    return 0.5 + 0.5 * sum / norm;
}

// The base noise: R Perlin-Worley (Perlin fBm, 4 cells, 4 octaves, dilated by Worley fBm at 4
// cells: remap(perlin, 0, 1, worley, 1), Schneider & Vos 2015), GBA Worley fBm at 8, 16, 32 cells.
vec4 cloudBaseNoise(vec3 p, uint seed) {
    real perlin = cn_perlinFbm(p, 4, 4, seed);
    real worley = cn_worleyFbm(p, 4, seed + 10u);
    real pw = clamp(worley + perlin * (1.0 - worley), 0.0, 1.0);
    return vec4(pw, cn_worleyFbm(p, 8, seed + 20u), cn_worleyFbm(p, 16, seed + 30u), cn_worleyFbm(p, 32, seed + 40u));
}

// The detail noise: RGB Worley fBm at 2, 4, 8 cells, A 1.
vec4 cloudDetailNoise(vec3 p, uint seed) {
    return vec4(cn_worleyFbm(p, 2, seed + 60u), cn_worleyFbm(p, 4, seed + 70u), cn_worleyFbm(p, 8, seed + 80u), 1.0);
}

// The curl noise: potential psi = 2-D Perlin fBm (4 cells, 5 octaves); RG its curl
// (d psi/dy, -d psi/dx) by central differences over e (one texel), / 8, clamped, as 0.5 + 0.5 v;
// B psi; A 1 (Bridson et al. 2007).
real cloudCurlPotential(vec2 p, uint seed) { return cn_perlinFbm2(p, 4, 5, seed + 50u); }

vec4 cloudCurlNoise(vec2 p, real e, uint seed) {
    real dx = (cloudCurlPotential(p + vec2(e, 0.0), seed) - cloudCurlPotential(p - vec2(e, 0.0), seed)) / (2.0 * e);
    real dy = (cloudCurlPotential(p + vec2(0.0, e), seed) - cloudCurlPotential(p - vec2(0.0, e), seed)) / (2.0 * e);
    vec2 v = clamp(vec2(dy, -dx) / 8.0, -1.0, 1.0);
    return vec4(0.5 + 0.5 * v.x, 0.5 + 0.5 * v.y, clamp(cloudCurlPotential(p, seed), 0.0, 1.0), 1.0);
}
