// Van Rhijn's factor of a thin emitting shell (the airglow's, the light pollution's), one source
// for the shader (nightsky.frag.glsl includes it) and C++ (vanRhijn() in nightsky.cpp compiles it
// in double, welkin/glsl_cpp.hpp): 1 / sqrt(1 - r2 sin^2 z) at cz = cos(zenith angle z), r2 =
// (R / (R + h))^2 for a shell at height h over a planet of radius R; sin^2 z = 1 - cz^2. The floor
// 1e-6 keeps a shell at the observer's height (r2 -> 1) finite at the horizon.
real night_vanRhijn(real cz, real r2) { return inversesqrt(max(1.0 - r2 * (1.0 - cz * cz), 1e-6)); }
