// The cloud droplets' phase functions and the light transfer of the Clouds element, in the GLSL
// subset of welkin/glsl_cpp.hpp: clouds.frag.glsl includes it, clouds.cpp compiles it in double as
// the cloudcpu:: functions the tests check (one text for the shader and its twin). The includer
// defines CLD_PI and the constants CLD_G_DRAINE, CLD_ALPHA_DRAINE, CLD_MS_S, CLD_MS_K, CLD_MS_Z,
// CLD_MS_A, CLD_MS_H, CLD_MS_C (per scaled optical depth), CLD_MS_Q, CLD_MS_MU_MIN, CLD_MS_AMBIENT,
// CLD_AMB_FORWARD and CLD_DIFFUSIVITY (the ambient's diffusion), CLD_SUN_K, CLD_SUN_Z, CLD_SUN_H,
// CLD_SUN_C (the lights' diffusion) and CLD_FW_W0..4, CLD_FW_G0..4 (the forward-peaked orders)
// (the shader gets them from clouds.cpp as defines, the C++ side defines them as its constexpr
// values), and CLD_W_DRAINE (the Draine lobe's share of the scattering, delta-M's scaling).
#include "clouds_transfer_table.shared.glsl"

// Henyey-Greenstein, 1/sr.
real cld_hg(real nu, real g) {
    real d = 1.0 + g * g - 2.0 * g * nu;
    return (1.0 - g * g) / (4.0 * CLD_PI * d * sqrt(d));
}
// The cloud droplets' phase function: the fit of Jendersie & d'Eon 2023 ("An approximate Mie
// scattering function for fog and cloud rendering", SIGGRAPH talk) to Lorenz-Mie at droplet
// diameter 20 um (r_eff 10 um), (1 - w_D) HG(g_peak) + w_D Draine(g_D, alpha): a sharp diffraction
// peak (g_peak 0.9946, within ~1 deg) and a Draine lobe (the forward lobe and the backward rise
// towards the fogbow and the glory). The constants CLD_G_PEAK, CLD_W_DRAINE, CLD_G_DRAINE,
// CLD_ALPHA_DRAINE and the transfer's CLD_MS_* come from clouds.cpp (cloudcpu, one source).
// Delta-M (Wiscombe 1977): the peak's share 1 - w_D of the extinction scatters within a degree, so
// it is treated as unscattered: the march uses the scaled extinction w_D sigma and the Draine lobe
// alone as the phase (C++: cloudcpu::scaledPhase).
real cld_draine(real nu, real g, real a) { return cld_hg(nu, g) * (1.0 + a * nu * nu) / (1.0 + a * (1.0 + 2.0 * g * g) / 3.0); }
real cld_scaledPhase(real nu) { return cld_draine(nu, CLD_G_DRAINE, CLD_ALPHA_DRAINE); }
// The forward-peaked low orders (C++: cloudcpu::forwardTransfer), per lux of a light and per unit
// scaled extinction, 1/sr: light that has scattered m = 0..4 times on its way in at small angles
// still travels about along the light's axis, so its share at scaled depth tauL is Poisson's
// tauL^m e^(-tauL) / m!, scattered towards the view by a lobe HG(nu, g_m) that widens with the
// order, times a weight w_m for what the order loses sideways. m = 0 adds to the Draine lobe's
// single scattering the diffraction peak's wings (1-5 deg) that delta-M counts as unscattered;
// m = 1..4 are orders 2-5. w_m, g_m: fitted to the path tracer's radiance of slabs of tau 0.5-32
// (skyelements/clouds/README.md, "Light transport").
real cld_forwardTransfer(real nu, real tauL) {
    real t1 = tauL, t2 = 0.5 * tauL * tauL, t3 = t2 * tauL / 3.0, t4 = 0.25 * t3 * tauL;
    return exp(-tauL) * (CLD_FW_W0 * cld_hg(nu, CLD_FW_G0) + CLD_FW_W1 * t1 * cld_hg(nu, CLD_FW_G1) + CLD_FW_W2 * t2 * cld_hg(nu, CLD_FW_G2)
                         + CLD_FW_W3 * t3 * cld_hg(nu, CLD_FW_G3) + CLD_FW_W4 * t4 * cld_hg(nu, CLD_FW_G4));
}
// Light transfer (skyelements/clouds/README.md, "Model"), per lux of a light and per unit scaled extinction,
// 1/sr, at a point with scaled optical depths tauL towards the light and tauB away from it (to
// the cloud's far side) and the light's cos(zenith) muL: the single scattering of the beam, the
// forward-peaked low orders (cld_forwardTransfer) and the multiple-scattered radiance of a slab
// along the light axis (diffusion in the transport optical depths s = CLD_MS_S tau: a mean
// radiance falling linearly from the lit side, plus the net flux's share towards the light's
// direction, nu), all fitted together against the path tracer's slab radiances and
// adding-doubling's fluxes. C++: cloudcpu::lightTransfer. cld_lightDiffusion: the diffusion term alone.
real cld_lightDiffusion(real nu, real tauL, real tauB, real muL) {
    real sL = CLD_MS_S * tauL, sB = CLD_MS_S * tauB;
    return CLD_SUN_K / CLD_PI * pow(max(muL, CLD_MS_MU_MIN), CLD_MS_Q) * (1.0 - exp(-CLD_SUN_C * (tauL + tauB)))
           * max(sB + CLD_SUN_Z + CLD_SUN_H * nu, 0.0) / (sL + sB + CLD_MS_A);
}
real cld_lightTransfer(real nu, real tauL, real tauB, real muL) {
    return cld_scaledPhase(nu) * exp(-tauL) + cld_forwardTransfer(nu, tauL) + cld_lightDiffusion(nu, tauL, tauB, muL);
}

// The cosine between the light and the normal of the cloud face through which it entered (C++:
// cloudcpu::litFaceCosine), from the sample's scaled depths towards the sky above it (tauUp, marched
// through the cloud's own density) and towards the light (tauL): in a deck lit at muL the two are
// in the ratio tauUp = muL tauL, so the ratio gives muL back; where the light entered a cumulus
// through a side facing it, the cloud above the sample is deeper than the light's path in
// (tauUp > tauL) and the face's cosine is 1. Clamped to [muL, 1] (0/0, the lit top itself, gives
// muL). The face is remembered over about one transport optical depth of the light's path, s_L =
// CLD_MS_S tauL: deeper, the diffuse light has come in through every face the light reaches and
// the slab's muL stands (weight e^(-s_L)). It replaces the light's cos(zenith) where the slab
// solution has it (the diffusion term's muL^q, the table's muL). No fitted constant
// (skyelements/clouds/README.md, "The lit face").
real cld_litFaceCosine(real tauUp, real tauL, real muL) {
    real m = max(muL, 0.0);
    return mix(m, clamp(tauUp / max(tauL, 1e-6), m, 1.0), exp(-CLD_MS_S * tauL));
}

// The depth to the far side that the diffusion term sees in a cloud of finite width (C++:
// cloudcpu::finiteBackDepth): tauB, the scaled depth to the cloud's far side along the light's
// axis, combined harmonically with tauWidth, the scaled depth across the cloud through the sample
// perpendicular to the light (both ways, horizontal): tauB tauWidth / (tauB + tauWidth). The
// light that diffuses into a cumulus leaks out through its sides as well as its far face, so the
// cumulus reflects and diffuses like a slab no thicker along the light than it is wide; in a deck
// (tauWidth >> tauB) it is tauB. No fitted constant (skyelements/clouds/README.md, "Finite clouds").
real cld_finiteBackDepth(real tauB, real tauWidth) { return tauB * tauWidth / max(tauB + tauWidth, 1e-9); }

// The diffusion term's angular correction (C++: cloudcpu::diffusionShape): the transfer table
// cld_msTable (clouds_transfer_table.shared.glsl, written by `welkin bench cloud-table`) holds,
// for a slab of optical depth tauAxis along the light's axis (unscaled; nodes 1, 2, 4 ... 256)
// lit at cos(zenith) muL (nodes 0.2, 0.4 ... 1), at the depth fraction depthFrac from its lit
// face (nodes 0, 0.25 ... 1), the ratio of adding-doubling's azimuth-averaged multiply scattered
// radiance there (its diffuse radiance less this model's single scattering and forward orders)
// to the diffusion term's, by the view ray's cos(zenith) muV (17 nodes on [-1, 1]: > 0 looking up,
// the light going down; < 0 looking down). Quadrilinear, clamped at the table's edges.
real cld_msTableAt(int i, int j, int m, int k) { return cld_msTable[((i * 5 + j) * 5 + m) * 17 + k]; }
real cld_msTableMuV(int i, int j, int m, int k, real fz) { return mix(cld_msTableAt(i, j, m, k), cld_msTableAt(i, j, m, k + 1), fz); }
real cld_msTableIJ(int i, int j, int m, int k, real fw, real fz) {
    return mix(cld_msTableMuV(i, j, m, k, fz), cld_msTableMuV(i, j, m + 1, k, fz), fw);
}
real cld_diffusionShape(real muV, real tauAxis, real muL, real depthFrac) {
    real x = clamp(log2(max(tauAxis, 1.0)), 0.0, 8.0);
    real y = clamp((muL - 0.2) / 0.2, 0.0, 4.0);
    real d = clamp(depthFrac * 4.0, 0.0, 4.0);
    real z = clamp((muV + 1.0) * 8.0, 0.0, 16.0);
    int i = int(floor(min(x, 7.0))), j = int(floor(min(y, 3.0))), m = int(floor(min(d, 3.0))), k = int(floor(min(z, 15.0)));
    real fx = x - real(i), fy = y - real(j), fw = d - real(m), fz = z - real(k);
    real a = mix(cld_msTableIJ(i, j, m, k, fw, fz), cld_msTableIJ(i, j + 1, m, k, fw, fz), fy);
    real b = mix(cld_msTableIJ(i + 1, j, m, k, fw, fz), cld_msTableIJ(i + 1, j + 1, m, k, fw, fz), fy);
    return mix(a, b, fx);
}
// How much the cloud around a sample is a deck (C++: cloudcpu::deckness), in [0, 1]: its scaled
// depth across, tauWidth (both ways, perpendicular to the light), against its scaled depth along
// the light's axis through the sample, tauAxis = tauL + tauB: (tauWidth - tauAxis) /
// (tauWidth + tauAxis), 0 for a cloud no wider than it is deep along the light (a cumulus), -> 1
// for a sheet far wider. No fitted constant.
real cld_deckness(real tauWidth, real tauAxis) {
    real x = clamp((tauWidth - tauAxis) / max(tauWidth + tauAxis, 1e-9), 0.0, 1.0);
    return x * x;
}
// The depth fraction at which the table is read (C++: cloudcpu::tableDepth): in a deck, the
// sample's own, tauL / (tauL + tauB) (inside a deck the light at the sample's depth, not its
// face's, is what the view ray collects); in a cumulus (deck = 0) the face the light leaves by
// towards the view: the far one (1) looking up, the lit one (0) looking down, blended across the
// horizontal over one node of muV (+-1/8). (skyelements/clouds/README.md, "The transfer table".)
real cld_tableDepth(real muV, real tauL, real tauB, real deck) {
    real face = clamp(0.5 + 4.0 * muV, 0.0, 1.0);
    return mix(face, tauL / max(tauL + tauB, 1e-9), deck);
}
// The lights' transfer with the table's correction (C++: cloudcpu::lightTransferTable): what the
// march uses. muV: the view ray's cos(zenith); deck: cld_deckness (0 a cumulus, 1 a wide deck).
real cld_lightTransferTable(real nu, real muV, real tauL, real tauB, real muL, real deck) {
    return cld_scaledPhase(nu) * exp(-tauL) + cld_forwardTransfer(nu, tauL)
           + cld_lightDiffusion(nu, tauL, tauB, muL) * cld_diffusionShape(muV, (tauL + tauB) / CLD_W_DRAINE, muL, cld_tableDepth(muV, tauL, tauB, deck));
}

// The ambient light's transfer (C++: cloudcpu::ambientTransfer), per lux of horizontal
// illuminance arriving as a uniform hemisphere from one side of the layer and per unit scaled
// extinction, 1/sr: the single scattering of the hemisphere (a share 1/2 + (F - 1/2) nu of it
// towards the view, attenuated by the diffusivity factor) plus the diffusion term at the diffuse
// field's slant depths (1.66 x the vertical), per horizontal lux (x 2 / (1 + q)). tauN, tauF: scaled vertical depths to the
// lit side and to the other; nu: cosine between the view ray and the direction to the lit side.
real cld_ambientTransfer(real nu, real tauN, real tauF) {
    real single = (0.5 + (CLD_AMB_FORWARD - 0.5) * nu) / CLD_PI * exp(-CLD_DIFFUSIVITY * tauN);
    real sN = CLD_DIFFUSIVITY * CLD_MS_S * tauN, sF = CLD_DIFFUSIVITY * CLD_MS_S * tauF;  // slant depths
    real multi = CLD_MS_AMBIENT * CLD_MS_K / CLD_PI * (1.0 - exp(-CLD_MS_C * (tauN + tauF)))
                * max(sF + CLD_MS_Z + CLD_MS_H * nu, 0.0) / (sN + sF + CLD_MS_A);
    return single + multi;
}
