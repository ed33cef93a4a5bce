// The depth pyramid's level 0 from a multisampled depth image.
#version 460

#define HIZ_MULTISAMPLED
#include "common/hiz_init.glsl"
