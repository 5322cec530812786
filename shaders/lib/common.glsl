// Preamble every vktg shader includes first: version-independent extensions and constants.
#ifndef VKTG_COMMON_GLSL
#define VKTG_COMMON_GLSL
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_float : require

const float kPi = 3.14159265358979323846;
const float kInvPi = 0.31830988618379067154;
const float kInfinity = 1.0 / 0.0;
#endif
