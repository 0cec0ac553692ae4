// The Mie tables' angle mapping welkin_mieUFromAngle(theta): scattering angle (rad) -> texture
// coordinate u. Its text is mie_angle.shared.glsl, which mie_tables.cpp compiles in double.
#include "mie_angle.shared.glsl"
