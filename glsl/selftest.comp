// Self-test for the Vulkan core (tests/vk_core.rs): exercises storage
// buffers, a uniform buffer, push constants, a specialization constant and
// global atomics. `spin` adds a bounded busy loop so a test can make a
// dispatch outlast a tiny fence timeout without ever hanging.
#version 460

layout(constant_id = 0) const uint LOCAL_SIZE = 64;
layout(local_size_x_id = 0) in;

layout(std430, set = 0, binding = 0) buffer Data {
    uint data[];
};

layout(std430, set = 0, binding = 1) buffer Counters {
    uint invocations; // one atomicAdd per live invocation
    uint index_sum;   // sum of the live invocation indices
    uint spin_hits;   // keeps the busy loop's result live; ~never incremented
};

layout(std140, set = 0, binding = 2) uniform Params {
    uint add;
};

layout(push_constant) uniform Push {
    uint mul;
    uint count;
    uint spin;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) {
        return;
    }
    data[i] = i * push.mul + add;
    atomicAdd(invocations, 1u);
    atomicAdd(index_sum, i);

    // A linear congruential generator the compiler cannot fold away.
    uint x = i;
    for (uint k = 0u; k < push.spin; ++k) {
        x = x * 1664525u + 1013904223u;
    }
    if (push.spin > 0u && x == 0xFFFFFFFFu) {
        atomicAdd(spin_hits, 1u);
    }
}
