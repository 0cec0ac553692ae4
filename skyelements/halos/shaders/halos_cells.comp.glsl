// The Halos element's adaptive cells (skyelements/halos/README.md, "Adaptive cells"; off by default):
// which parts of the real-time grid (halos_grid.vert.glsl) fetch the table per pixel and which
// draw their corners' values interpolated. One invocation per 64-pixel cell tests the cell whole,
// then, if it is not smooth, its quarters, and lists the pieces: smooth ones in one list, those
// that fetch in the other (a cell with no smooth quarter fetches whole), each list with its
// indirect draw command (two draws: the fragments never branch). (A further split into sixteenths
// cost more than it saved on llvmpipe: skyelements/halos/README.md.)
//
// The test of a piece: its four corners' table values are what the smooth draw interpolates
// (over the triangles (0,0)-(1,0)-(1,1) and (0,0)-(1,1)-(0,1), linearly in the pixel); at points
// of the piece no more than one block of the maps apart (edges and corners included) the
// difference from the per-pixel fetch is bounded by |mean - interpolation| + detail, where mean is
// the table's block means (bilinear) and detail the largest |table - mean| over the block and its
// eight neighbours (Halos::updateOctMaps: what lies between two samples); the piece is smooth if
// that stays under u_rel x (the interpolated halo light + u_floor x the transmittance) in each
// colour channel and u_rel x the transmittance in alpha at every point above the horizon. u_floor
// is a lower bound of the clear sky's radiance behind the layer over the light's illuminance, so
// the bound is a fraction u_rel of what the pixel shows. Needs engine/camera.glsl before it.
layout(local_size_x = 16) in;
layout(binding = WELKIN_BINDING_HALOS_TABLE) uniform sampler2D u_haloTable;
layout(binding = WELKIN_BINDING_HALOS_MEAN) uniform sampler2D u_mean;      // block means, M x M, bilinear
layout(binding = WELKIN_BINDING_HALOS_DETAIL) uniform sampler2D u_detail;  // block detail, M x M, texelFetch
layout(std430, binding = WELKIN_BINDING_HALOS_CELLS) buffer HalosCells {
    uint u_draws[8];  // DrawArraysIndirectCommand x 2: [0..3] the smooth list's, [4..7] the fetching list's
    uint u_leaves[];  // [0, u_listSize): the smooth pieces; [u_listSize, 2 u_listSize): those that fetch (5 cell + slot)
};
uniform ivec2 u_grid;      // cells across, down
uniform float u_cellPx;    // cell size, pixels
uniform vec3 u_lightX;     // the table's frame, as halos_grid.vert.glsl's
uniform vec3 u_lightY;
uniform vec3 u_lightZ;
uniform float u_muHorizon;
uniform int u_mapSize;     // M
uniform uint u_listSize;   // entries per list
uniform float u_rel;       // tolerance, a fraction of the pixel's light (Halos::kCellTolerance)
uniform vec3 u_floor;      // the sky's least radiance behind the layer over the light's illuminance, 1/sr

vec3 rayAt(vec2 px) {
    vec3 d;
    welkin_viewDirection(px, d);
    return d / dot(d, mat3(welkin_cameraToWorld)[2]);  // affine in the pixel
}
vec2 uvOf(vec3 r) {
    vec3 q = vec3(dot(r, u_lightX), dot(r, u_lightY), dot(r, u_lightZ));
    vec3 a = abs(q);
    return vec2(q.x + q.z, q.x - q.z) / (a.x + a.y + a.z) * 0.5 + 0.5;
}

// True if the piece [p0, p1] (pixels) may be drawn from its corners' values.
bool smoothPiece(vec2 p0, vec2 p1) {
    vec3 r00 = rayAt(p0), r10 = rayAt(vec2(p1.x, p0.y)), r01 = rayAt(vec2(p0.x, p1.y)), r11 = rayAt(p1);
    vec2 u00 = uvOf(r00), u10 = uvOf(r10), u01 = uvOf(r01), u11 = uvOf(r11);
    vec4 t00 = textureLod(u_haloTable, u00, 0.0), t10 = textureLod(u_haloTable, u10, 0.0);
    vec4 t01 = textureLod(u_haloTable, u01, 0.0), t11 = textureLod(u_haloTable, u11, 0.0);
    // Samples one block apart at most: the piece's largest extent on the map, in blocks (the
    // octahedral map is smooth within an octant; its folds are caught by the samples' spacing).
    float span = max(max(distance(u00, u11), distance(u10, u01)), max(max(distance(u00, u10), distance(u01, u11)),
                                                                      max(distance(u00, u01), distance(u10, u11))));
    int S = clamp(int(ceil(span * float(u_mapSize))) + 1, 2, 24);
    float inv = 1.0 / float(S - 1);
    for (int b = 0; b < S; ++b)
        for (int a = 0; a < S; ++a) {
            float u = float(a) * inv, v = float(b) * inv;
            vec3 r = r00 + u * (r10 - r00) + v * (r01 - r00);
            if (r.z - u_muHorizon * length(r) < 0.0) continue;  // the ground: clipped
            vec4 lin = u >= v ? t00 + u * (t10 - t00) + v * (t11 - t10) : t00 + v * (t01 - t00) + u * (t11 - t01);
            vec2 uv = uvOf(r);
            vec4 e = abs(textureLod(u_mean, uv, 0.0) - lin) + texelFetch(u_detail, clamp(ivec2(uv * float(u_mapSize)), ivec2(0), ivec2(u_mapSize - 1)), 0);
            vec4 tol = u_rel * vec4(lin.rgb + u_floor * lin.a, lin.a);
            if (any(greaterThan(e, tol))) return false;
        }
    return true;
}

void emit(bool smoothLeaf, uint leaf) {
    uint i = atomicAdd(u_draws[smoothLeaf ? 0 : 4], 6u) / 6u;
    u_leaves[(smoothLeaf ? 0u : u_listSize) + i] = leaf;
}

void main() {
    uint cell = gl_GlobalInvocationID.x;
    if (cell >= uint(u_grid.x * u_grid.y)) return;
    vec2 size = welkin_viewport.xy;
    vec2 o = vec2(float(int(cell) % u_grid.x), float(int(cell) / u_grid.x)) * u_cellPx;
    uint base = 5u * cell;
    if (smoothPiece(o, min(o + u_cellPx, size))) {
        emit(true, base);
        return;
    }
    // The quarters (those wholly outside the image are left out); none smooth: the cell whole.
    float h = 0.5 * u_cellPx;
    bool quarterSmooth[4];
    bool any = false;
    for (int q = 0; q < 4; ++q) {
        vec2 qo = o + vec2(float(q & 1), float(q >> 1)) * h;
        quarterSmooth[q] = qo.x < size.x && qo.y < size.y && smoothPiece(qo, min(qo + h, size));
        any = any || quarterSmooth[q];
    }
    if (!any) {
        emit(false, base);
        return;
    }
    for (int q = 0; q < 4; ++q) {
        vec2 qo = o + vec2(float(q & 1), float(q >> 1)) * h;
        if (qo.x < size.x && qo.y < size.y) emit(quarterSmooth[q], base + 1u + uint(q));
    }
}
