// Floating-point building blocks in a fixed operation order: the twin of
// src/patch/ops.rs. Every local that feeds a position or a decision is
// `precise` (and so is every function result), which forbids the compiler to
// reassociate sums or fuse multiply-adds; `precise` on a caller's variable
// does not reach into a called function, so it is repeated here.
#ifndef OPS_GLSL
#define OPS_GLSL

#include "constants.glsl"

// f32(1/3) and f32(2/3) from their bits (glslang does not fold
// uintBitsToFloat into a constant, and a decimal literal invites doubt).
#define THIRD uintBitsToFloat(THIRD_BITS)
#define TWO_THIRDS uintBitsToFloat(TWO_THIRDS_BITS)

// (a.x*b.x + a.y*b.y) + a.z*b.z
precise float dot3(vec3 a, vec3 b) {
    precise float r = (a.x * b.x + a.y * b.y) + a.z * b.z;
    return r;
}

// a × b, each component p*q - r*s.
precise vec3 cross3(vec3 a, vec3 b) {
    precise float x = a.y * b.z - a.z * b.y;
    precise float y = a.z * b.x - a.x * b.z;
    precise float z = a.x * b.y - a.y * b.x;
    return vec3(x, y, z);
}

// ((r.x*p.x + r.y*p.y) + r.z*p.z) + r.w
precise float affine_row(vec4 r, vec3 p) {
    precise float x = ((r.x * p.x + r.y * p.y) + r.z * p.z) + r.w;
    return x;
}

// 2^-l from its bit pattern (exp2 and division are not exact on a GPU).
float pow2_neg(uint l) {
    return uintBitsToFloat((127u - l) << 23);
}

// Comparisons written out as in Rust (min/max built-ins leave NaN and
// signed-zero behaviour open; inputs are finite, this keeps the twins exact).
vec3 min3(vec3 a, vec3 b) {
    return vec3(b.x < a.x ? b.x : a.x, b.y < a.y ? b.y : a.y, b.z < a.z ? b.z : a.z);
}

vec3 max3(vec3 a, vec3 b) {
    return vec3(b.x > a.x ? b.x : a.x, b.y > a.y ? b.y : a.y, b.z > a.z ? b.z : a.z);
}

float minf(float a, float b) {
    return b < a ? b : a;
}

float maxf(float a, float b) {
    return b > a ? b : a;
}

#endif
