//! The Vulkan core: context and device selection, memory, commands and
//! barriers, timestamps, shaders and compute pipelines.

pub mod commands;
pub mod context;
pub mod debug;
pub mod device;
pub mod error;
pub mod info;
pub mod memory;
pub mod pipeline;
pub mod query;
pub mod shader;

pub use commands::{buffer_barrier, host_read_barrier, image_barrier, memory_barrier, Access};
pub use context::{Context, ContextOptions, DEFAULT_FENCE_TIMEOUT};
pub use device::DeviceSelector;
pub use error::{VkError, VkResult};
pub use info::{describe, DeviceInfo, DeviceKind, DeviceLimits, MeshShaderInfo, OptionalFeatures};
pub use memory::{Buffer, Image, ImageDesc, MemoryLocation};
pub use pipeline::{
    write_buffers, ComputePipeline, ComputePipelineDesc, DescriptorPool, Pipeline, PipelineLayout,
    SetLayout, Specialization,
};
pub use query::GpuTimer;
pub use shader::{load_spirv, spirv_dir, spirv_path, spirv_words, ShaderModule, SPIRV_DIR_ENV};
