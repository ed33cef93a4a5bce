//! The Vulkan core: context and device selection, memory, commands and
//! barriers, frames in flight, timestamps, shaders, layouts and pipelines.

pub mod barrier;
pub mod commands;
pub mod context;
pub mod debug;
pub mod device;
pub mod error;
pub mod frames;
pub mod info;
pub mod layout;
pub mod memory;
pub mod pass;
pub mod pipeline;
pub mod query;
pub mod reflect;
pub mod shader;
pub mod swapchain;
mod track;

pub use barrier::{host_read_barrier, memory_barrier, Access};
pub use context::{
    default_fence_timeout, device_leaked, env_fence_timeout, parse_timeout, set_fence_timeout,
    Context, ContextOptions, WindowHandles, COMPILE_ALLOWANCE, DEFAULT_FENCE_TIMEOUT,
};
pub use device::DeviceSelector;
pub use error::{seconds_text, VkError, VkResult, TIMEOUT_ENV};
pub use frames::{FrameRing, Progress, ProgressSink, MAX_FRAME_PARTS};
pub use info::{describe, DeviceInfo, DeviceKind, DeviceLimits, MeshShaderInfo, OptionalFeatures};
pub use layout::{
    all_stages, reflect_shader, set_bindings, undynamic, Binding, BufferBinding, DescriptorSet,
    LayoutBinding, NoPush, PipelineLayout, Sampler, SetLayout,
};
pub use memory::{
    buffer_barrier, fill_buffer, image_barrier, Buffer, Image, ImageDesc, MemoryLocation,
};
pub use pass::{Pass, Recorder, Res};
pub use pipeline::{DepthState, GraphicsDesc, Pipeline, Specialization};
pub use query::{GpuTimer, PrimitiveCounter, PrimitiveQuery};
pub use reflect::{reflect, Reflection};
pub use shader::{
    embedded_shaders, load_spirv, load_spirv_file, spirv_override_dir, spirv_words, ShaderModule,
    SPIRV_DIR_ENV,
};
pub use swapchain::{Acquired, PresentPacing, Swapchain};
