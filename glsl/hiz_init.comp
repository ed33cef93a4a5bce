// The depth pyramid's level 0 from a single-sampled depth image.
#version 460

#include "common/hiz_init.glsl"
