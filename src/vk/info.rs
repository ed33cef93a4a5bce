//! What we know about the chosen device: identity, limits, and which optional
//! features were enabled. Filled once at context creation; read everywhere.

use ash::vk;
use std::fmt::Write as _;

/// The kind of a physical device, in the order `Auto` prefers them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum DeviceKind {
    /// A discrete GPU.
    Discrete,
    /// A GPU sharing memory with the CPU.
    Integrated,
    /// A GPU seen through a virtualisation layer.
    Virtual,
    /// A software rasteriser running on the CPU (lavapipe, SwiftShader).
    Cpu,
    /// Anything else the driver reports.
    Other,
}

impl DeviceKind {
    /// Maps Vulkan's device type.
    pub fn from_vk(ty: vk::PhysicalDeviceType) -> Self {
        match ty {
            vk::PhysicalDeviceType::DISCRETE_GPU => Self::Discrete,
            vk::PhysicalDeviceType::INTEGRATED_GPU => Self::Integrated,
            vk::PhysicalDeviceType::VIRTUAL_GPU => Self::Virtual,
            vk::PhysicalDeviceType::CPU => Self::Cpu,
            _ => Self::Other,
        }
    }

    /// Human-readable label.
    pub fn label(self) -> &'static str {
        match self {
            Self::Discrete => "discrete GPU",
            Self::Integrated => "integrated GPU",
            Self::Virtual => "virtual GPU",
            Self::Cpu => "CPU device (software rasteriser)",
            Self::Other => "other device",
        }
    }
}

/// Optional device features; each is `true` only if it was enabled.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OptionalFeatures {
    /// VK_EXT_mesh_shader with both taskShader and meshShader.
    pub mesh_shader: bool,
    /// `multiDrawIndirect` (drawCount > 1 in one indirect call).
    pub multi_draw_indirect: bool,
    /// `drawIndirectCount` (Vulkan 1.2).
    pub draw_indirect_count: bool,
    /// `drawIndirectFirstInstance`: an indirect draw's first instance other
    /// than 0 (the levels of detail's culled draws name their instance so).
    pub draw_indirect_first_instance: bool,
    /// `vertexPipelineStoresAndAtomics`.
    pub vertex_pipeline_stores_and_atomics: bool,
    /// `fragmentStoresAndAtomics`.
    pub fragment_stores_and_atomics: bool,
    /// `shaderInt64`.
    pub shader_int64: bool,
    /// `subgroupSizeControl` (Vulkan 1.3).
    pub subgroup_size_control: bool,
    /// `computeFullSubgroups` (Vulkan 1.3).
    pub compute_full_subgroups: bool,
    /// `pipelineStatisticsQuery`.
    pub pipeline_statistics_query: bool,
    /// `tessellationShader`.
    pub tessellation_shader: bool,
    /// `geometryShader`.
    pub geometry_shader: bool,
    /// VK_EXT_primitives_generated_query with `primitivesGeneratedQuery`:
    /// primitives counted at the end of vertex and tessellation pipelines.
    pub primitives_generated_query: bool,
    /// `meshShaderQueries` (VK_EXT_mesh_shader): primitives counted at the end
    /// of mesh pipelines.
    pub mesh_shader_queries: bool,
    /// `vulkanMemoryModel` and `vulkanMemoryModelDeviceScope` (Vulkan 1.2):
    /// the subdivision kernels' acquire/release atomics between workgroups.
    pub vulkan_memory_model: bool,
}

impl OptionalFeatures {
    /// (name, enabled) pairs in a stable order, for reports.
    pub fn list(&self) -> [(&'static str, bool); 15] {
        [
            ("mesh shader (VK_EXT_mesh_shader)", self.mesh_shader),
            ("multiDrawIndirect", self.multi_draw_indirect),
            ("drawIndirectCount", self.draw_indirect_count),
            (
                "drawIndirectFirstInstance",
                self.draw_indirect_first_instance,
            ),
            (
                "vertexPipelineStoresAndAtomics",
                self.vertex_pipeline_stores_and_atomics,
            ),
            ("fragmentStoresAndAtomics", self.fragment_stores_and_atomics),
            ("shaderInt64", self.shader_int64),
            ("subgroupSizeControl", self.subgroup_size_control),
            ("computeFullSubgroups", self.compute_full_subgroups),
            ("pipelineStatisticsQuery", self.pipeline_statistics_query),
            ("tessellationShader", self.tessellation_shader),
            ("geometryShader", self.geometry_shader),
            (
                "primitivesGeneratedQuery (VK_EXT_primitives_generated_query)",
                self.primitives_generated_query,
            ),
            ("meshShaderQueries", self.mesh_shader_queries),
            ("vulkanMemoryModel (device scope)", self.vulkan_memory_model),
        ]
    }
}

/// Device limits the renderer sizes its work by.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DeviceLimits {
    /// `maxComputeWorkGroupInvocations`.
    pub max_compute_work_group_invocations: u32,
    /// `maxComputeWorkGroupSize`.
    pub max_compute_work_group_size: [u32; 3],
    /// `maxComputeWorkGroupCount`.
    pub max_compute_work_group_count: [u32; 3],
    /// `maxComputeSharedMemorySize` in bytes.
    pub max_compute_shared_memory_size: u32,
    /// `maxStorageBufferRange` in bytes.
    pub max_storage_buffer_range: u32,
    /// `maxUniformBufferRange` in bytes.
    pub max_uniform_buffer_range: u32,
    /// `maxPushConstantsSize` in bytes.
    pub max_push_constants_size: u32,
    /// `minStorageBufferOffsetAlignment` in bytes.
    pub min_storage_buffer_offset_alignment: u64,
    /// `minUniformBufferOffsetAlignment`.
    pub min_uniform_buffer_offset_alignment: u64,
    /// `maxDrawIndirectCount`.
    pub max_draw_indirect_count: u32,
    /// `maxTessellationGenerationLevel` (0 without tessellation).
    pub max_tessellation_generation_level: u32,
    /// Sample counts colour and depth attachments both support.
    pub framebuffer_sample_counts: vk::SampleCountFlags,
}

impl DeviceLimits {
    /// The samples per pixel of 1, 2, 4 and 8 (what `--msaa` takes) that
    /// colour and depth attachments both support, ascending.
    pub fn msaa_sample_counts(&self) -> Vec<u32> {
        [1, 2, 4, 8]
            .into_iter()
            .filter(|&n| {
                self.framebuffer_sample_counts
                    .contains(vk::SampleCountFlags::from_raw(n))
            })
            .collect()
    }
}

/// VK_EXT_mesh_shader properties.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MeshShaderInfo {
    /// `maxMeshOutputVertices`.
    pub max_mesh_output_vertices: u32,
    /// `maxMeshOutputPrimitives`.
    pub max_mesh_output_primitives: u32,
    /// `maxMeshWorkGroupInvocations`.
    pub max_mesh_work_group_invocations: u32,
    /// `maxTaskWorkGroupInvocations`.
    pub max_task_work_group_invocations: u32,
    /// `maxTaskWorkGroupCount` per dimension.
    pub max_task_work_group_count: [u32; 3],
    /// `maxTaskWorkGroupTotalCount`.
    pub max_task_work_group_total_count: u32,
    /// `maxTaskPayloadSize` in bytes.
    pub max_task_payload_size: u32,
    /// `maxPreferredMeshWorkGroupInvocations`.
    pub max_preferred_mesh_work_group_invocations: u32,
    /// `maxPreferredTaskWorkGroupInvocations`.
    pub max_preferred_task_work_group_invocations: u32,
}

/// Identity, limits and enabled features of the device a context runs on.
#[derive(Debug, Clone)]
pub struct DeviceInfo {
    /// Index in the instance's physical-device enumeration (what `--device N` takes).
    pub index: usize,
    /// `deviceName`.
    pub name: String,
    /// Driver name from VkPhysicalDeviceDriverProperties.
    pub driver_name: String,
    /// Driver info string (version details) from VkPhysicalDeviceDriverProperties.
    pub driver_info: String,
    /// Driver id.
    pub driver_id: vk::DriverId,
    /// The device type.
    pub kind: DeviceKind,
    /// A software device (lavapipe/llvmpipe/SwiftShader or type CPU): results
    /// are correct but timings say nothing about GPUs.
    pub is_cpu: bool,
    /// PCI vendor id.
    pub vendor_id: u32,
    /// PCI device id.
    pub device_id: u32,
    /// The device's Vulkan API version (packed).
    pub api_version: u32,
    /// The queue family our single queue comes from.
    pub queue_family: u32,
    /// Default subgroup size.
    pub subgroup_size: u32,
    /// Smallest subgroup size (subgroup size control).
    pub min_subgroup_size: u32,
    /// Largest subgroup size (subgroup size control).
    pub max_subgroup_size: u32,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period: f32,
    /// Meaningful bits of a timestamp on our queue (0: no timestamps).
    pub timestamp_valid_bits: u32,
    /// Limits we size work by.
    pub limits: DeviceLimits,
    /// Mesh shader properties, if the extension is enabled.
    pub mesh: Option<MeshShaderInfo>,
    /// Streaming multiprocessors (NVIDIA, `VK_NV_shader_sm_builtins`) or
    /// compute units (AMD, `VK_AMD_shader_core_properties`), where the
    /// driver says: what a persistent kernel's launch is sized by.
    pub compute_units: Option<u32>,
    /// Compute shaders have the subgroup operations the kernels use
    /// (basic, arithmetic, ballot).
    pub compute_subgroup_ops: bool,
    /// Optional features that were enabled.
    pub features: OptionalFeatures,
}

impl DeviceInfo {
    /// Whether task + mesh shaders are enabled.
    pub fn has_mesh_shader(&self) -> bool {
        self.features.mesh_shader
    }

    /// "major.minor.patch" of the device's API version.
    pub fn api_version_string(&self) -> String {
        version_string(self.api_version)
    }

    /// The kind label, naming software devices as CPU devices.
    pub fn kind_label(&self) -> &'static str {
        if self.is_cpu {
            DeviceKind::Cpu.label()
        } else {
            self.kind.label()
        }
    }
}

/// Formats a packed Vulkan version.
pub fn version_string(v: u32) -> String {
    format!(
        "{}.{}.{}",
        vk::api_version_major(v),
        vk::api_version_minor(v),
        vk::api_version_patch(v)
    )
}

/// Whether a device is a software rasteriser, by type, driver id or name.
pub(crate) fn looks_like_cpu(kind: DeviceKind, driver_id: vk::DriverId, name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    kind == DeviceKind::Cpu
        || driver_id == vk::DriverId::MESA_LLVMPIPE
        || driver_id == vk::DriverId::GOOGLE_SWIFTSHADER
        || lower.contains("llvmpipe")
        || lower.contains("lavapipe")
        || lower.contains("swiftshader")
}

/// A multi-line human-readable summary of a device (for `bezier-subdiv info`).
pub fn describe(info: &DeviceInfo) -> String {
    let mut s = String::new();
    // Writing into a String cannot fail; the results are ignored on purpose
    // (here and in the helpers).
    describe_identity(&mut s, info);
    describe_limits(&mut s, &info.limits);
    describe_mesh(&mut s, info.mesh.as_ref());
    if info.features.tessellation_shader {
        let _ = writeln!(
            s,
            "  tessellation:    max level {}",
            info.limits.max_tessellation_generation_level
        );
    }
    describe_features(&mut s, &info.features);
    s
}

/// The summary's first lines: the device, its driver, API version and
/// queue (subgroups, timestamps).
fn describe_identity(s: &mut String, info: &DeviceInfo) {
    let _ = writeln!(s, "device {}: {}", info.index, info.name);
    let _ = writeln!(s, "  type:            {}", info.kind_label());
    if info.is_cpu {
        let _ = writeln!(
            s,
            "  note:            CPU device: results are valid, timings do not reflect a GPU"
        );
    }
    let _ = writeln!(
        s,
        "  driver:          {} ({}) [{:?}]",
        info.driver_name, info.driver_info, info.driver_id
    );
    let _ = writeln!(
        s,
        "  vendor/device:   {:#06x}/{:#06x}",
        info.vendor_id, info.device_id
    );
    let _ = writeln!(s, "  Vulkan API:      {}", info.api_version_string());
    let _ = writeln!(s, "  queue family:    {}", info.queue_family);
    let _ = writeln!(
        s,
        "  subgroup size:   {} (min {}, max {})",
        info.subgroup_size, info.min_subgroup_size, info.max_subgroup_size
    );
    let _ = writeln!(
        s,
        "  timestamps:      {} valid bits, {} ns/tick",
        info.timestamp_valid_bits, info.timestamp_period
    );
    if let Some(units) = info.compute_units {
        let _ = writeln!(s, "  compute units:   {units} (SMs or CUs)");
    }
}

/// The summary's lines on the limits work is sized by.
fn describe_limits(s: &mut String, l: &DeviceLimits) {
    let _ = writeln!(
        s,
        "  compute:         {} invocations/workgroup, size {:?}, count {:?}, {} KiB shared",
        l.max_compute_work_group_invocations,
        l.max_compute_work_group_size,
        l.max_compute_work_group_count,
        l.max_compute_shared_memory_size / 1024
    );
    let _ = writeln!(
        s,
        "  buffers:         storage range {} MiB, uniform range {} KiB, push constants {} B",
        l.max_storage_buffer_range / (1024 * 1024),
        l.max_uniform_buffer_range / 1024,
        l.max_push_constants_size
    );
    let _ = writeln!(
        s,
        "  indirect:        max draw count {}",
        l.max_draw_indirect_count
    );
    let samples: Vec<String> = l.msaa_sample_counts().iter().map(u32::to_string).collect();
    let _ = writeln!(
        s,
        "  MSAA (--msaa):   {} samples per pixel",
        samples.join(", ")
    );
}

/// The summary's lines on mesh and task shaders.
fn describe_mesh(s: &mut String, mesh: Option<&MeshShaderInfo>) {
    if let Some(m) = mesh {
        let _ = writeln!(
            s,
            "  mesh shader:     {} vertices / {} primitives out, {} invocations (preferred {}), payload {} B",
            m.max_mesh_output_vertices,
            m.max_mesh_output_primitives,
            m.max_mesh_work_group_invocations,
            m.max_preferred_mesh_work_group_invocations,
            m.max_task_payload_size
        );
        let _ = writeln!(
            s,
            "  task shader:     {} invocations (preferred {}), workgroups {:?} (total {})",
            m.max_task_work_group_invocations,
            m.max_preferred_task_work_group_invocations,
            m.max_task_work_group_count,
            m.max_task_work_group_total_count
        );
    } else {
        let _ = writeln!(s, "  mesh shader:     not available");
    }
}

/// The summary's last lines: the optional features on and off (no
/// newline after the last).
fn describe_features(s: &mut String, features: &OptionalFeatures) {
    let enabled: Vec<&str> = features
        .list()
        .iter()
        .filter(|(_, on)| *on)
        .map(|(name, _)| *name)
        .collect();
    let missing: Vec<&str> = features
        .list()
        .iter()
        .filter(|(_, on)| !*on)
        .map(|(name, _)| *name)
        .collect();
    let _ = writeln!(s, "  features on:     {}", join_or_none(&enabled));
    let _ = write!(s, "  features off:    {}", join_or_none(&missing));
}

fn join_or_none(items: &[&str]) -> String {
    if items.is_empty() {
        String::from("(none)")
    } else {
        items.join(", ")
    }
}
