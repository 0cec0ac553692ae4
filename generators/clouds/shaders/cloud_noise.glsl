// Tileable noise primitives of the cloud noise generators (cn_hash, cn_worley, cn_worleyFbm,
// cn_perlin, cn_perlinFbm, cn_perlin2, cn_perlinFbm2, and the textures' texels): one source with
// the CPU twin, cloud_noise.shared.glsl (documented there).
#include "cloud_noise.shared.glsl"
