//! Physical-device enumeration, selection (`--device`) and logical-device
//! creation with the features the renderer needs.

use super::error::{VkError, VkResult, VkResultExt};
use super::info::{
    looks_like_cpu, version_string, DeviceInfo, DeviceKind, DeviceLimits, MeshShaderInfo,
    OptionalFeatures,
};
use ash::vk;
use std::fmt;
use std::str::FromStr;

/// Which physical device to use.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub enum DeviceSelector {
    /// Prefer a discrete GPU, then integrated, virtual, and finally a CPU device.
    #[default]
    Auto,
    /// The device at this enumeration index.
    Index(usize),
    /// The first device whose name contains this (case-insensitive).
    Name(String),
}

impl FromStr for DeviceSelector {
    type Err = std::convert::Infallible;

    /// "auto" (or empty), a number, or a name substring.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        Ok(if s.is_empty() || s.eq_ignore_ascii_case("auto") {
            Self::Auto
        } else if let Ok(i) = s.parse::<usize>() {
            Self::Index(i)
        } else {
            Self::Name(s.to_owned())
        })
    }
}

impl fmt::Display for DeviceSelector {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Auto => write!(f, "auto"),
            Self::Index(i) => write!(f, "{i}"),
            Self::Name(n) => write!(f, "{n}"),
        }
    }
}

/// One enumerated physical device and what it can do.
pub(crate) struct Candidate {
    pub handle: vk::PhysicalDevice,
    /// Everything except `features`, which holds what is *available*.
    pub info: DeviceInfo,
    /// Why the device cannot be used at all (empty: usable).
    pub problems: Vec<String>,
}

impl Candidate {
    fn summary(&self) -> String {
        let status = if self.problems.is_empty() {
            if self.info.features.mesh_shader {
                String::from("usable, mesh shaders")
            } else {
                String::from("usable, no mesh shaders")
            }
        } else {
            format!("unusable: {}", self.problems.join("; "))
        };
        format!(
            "  [{}] {} ({}, Vulkan {}) — {}",
            self.info.index,
            self.info.name,
            self.info.kind_label(),
            self.info.api_version_string(),
            status
        )
    }
}

/// One line per candidate, for error messages and logs.
pub(crate) fn device_list(candidates: &[Candidate]) -> String {
    if candidates.is_empty() {
        return String::from("  (none: is a Vulkan driver installed, e.g. mesa-vulkan-drivers?)");
    }
    candidates
        .iter()
        .map(Candidate::summary)
        .collect::<Vec<_>>()
        .join("\n")
}

/// Enumerates all physical devices with their properties and support.
pub(crate) fn enumerate(instance: &ash::Instance) -> VkResult<Vec<Candidate>> {
    let handles =
        unsafe { instance.enumerate_physical_devices() }.ctx("vkEnumeratePhysicalDevices")?;
    handles
        .into_iter()
        .enumerate()
        .map(|(index, handle)| probe(instance, index, handle))
        .collect()
}

/// The subgroup operations the level kernels' scans, searches and
/// visibility bits use in compute shaders.
const REQUIRED_SUBGROUP_OPS: vk::SubgroupFeatureFlags = vk::SubgroupFeatureFlags::from_raw(
    vk::SubgroupFeatureFlags::BASIC.as_raw()
        | vk::SubgroupFeatureFlags::ARITHMETIC.as_raw()
        | vk::SubgroupFeatureFlags::BALLOT.as_raw(),
);

fn has_extension(list: &[vk::ExtensionProperties], name: &std::ffi::CStr) -> bool {
    list.iter()
        .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name))
}

fn probe(instance: &ash::Instance, index: usize, pd: vk::PhysicalDevice) -> VkResult<Candidate> {
    let (mut info, mut problems) = basic_info(instance, index, pd);
    if info.api_version < vk::API_VERSION_1_3 {
        // Vulkan 1.2/1.3 property and feature structs may not be queried on
        // an older device, so stop at the basic properties.
        problems.push(format!(
            "supports Vulkan {} only; bezier-subdiv needs 1.3 (update the driver)",
            version_string(info.api_version)
        ));
        return Ok(Candidate {
            handle: pd,
            info,
            problems,
        });
    }
    let extensions = unsafe { instance.enumerate_device_extension_properties(pd) }
        .ctx("vkEnumerateDeviceExtensionProperties")?;
    let mesh_ext = has_extension(&extensions, ash::ext::mesh_shader::NAME);
    // The primitives-generated query extension depends on transform feedback.
    let prims_ext = has_extension(&extensions, ash::ext::primitives_generated_query::NAME)
        && has_extension(&extensions, ash::ext::transform_feedback::NAME);
    let mesh_props = read_properties(instance, pd, mesh_ext, &mut info);
    info.compute_units = compute_units(instance, pd, &extensions);
    problems.extend(read_features(
        instance,
        pd,
        (mesh_ext, prims_ext),
        &mut info,
    ));
    if info.features.mesh_shader {
        info.mesh = Some(mesh_info(&mesh_props));
    }

    Ok(Candidate {
        handle: pd,
        info,
        problems,
    })
}

/// What Vulkan 1.0 properties say: name, kind, limits, the queue family
/// with graphics and compute; and the problem when there is none.
fn basic_info(
    instance: &ash::Instance,
    index: usize,
    pd: vk::PhysicalDevice,
) -> (DeviceInfo, Vec<String>) {
    let base = unsafe { instance.get_physical_device_properties(pd) };
    let name = base
        .device_name_as_c_str()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|_| String::from("(unnamed device)"));
    let kind = DeviceKind::from_vk(base.device_type);
    let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
    let family = families.iter().position(|f| {
        f.queue_count > 0
            && f.queue_flags
                .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
    });
    let info = DeviceInfo {
        index,
        name: name.clone(),
        driver_name: String::new(),
        driver_info: String::new(),
        driver_id: vk::DriverId::default(),
        kind,
        is_cpu: looks_like_cpu(kind, vk::DriverId::default(), &name),
        vendor_id: base.vendor_id,
        device_id: base.device_id,
        api_version: base.api_version,
        queue_family: family.unwrap_or(0) as u32,
        subgroup_size: 0,
        min_subgroup_size: 0,
        max_subgroup_size: 0,
        timestamp_period: base.limits.timestamp_period,
        timestamp_valid_bits: family.map_or(0, |f| families[f].timestamp_valid_bits),
        limits: limits_from(&base.limits),
        mesh: None,
        compute_units: None,
        compute_subgroup_ops: false,
        features: OptionalFeatures::default(),
    };
    let mut problems = Vec::new();
    if family.is_none() {
        problems.push(String::from(
            "no queue family with both graphics and compute",
        ));
    }
    (info, problems)
}

/// Driver identity and subgroup sizes into `info`; returns the mesh-shader
/// properties (zero without the extension).
fn read_properties(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    mesh_ext: bool,
    info: &mut DeviceInfo,
) -> vk::PhysicalDeviceMeshShaderPropertiesEXT<'static> {
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut p11 = vk::PhysicalDeviceVulkan11Properties::default();
    let mut p13 = vk::PhysicalDeviceVulkan13Properties::default();
    let mut pmesh = vk::PhysicalDeviceMeshShaderPropertiesEXT::default();
    let mut props = vk::PhysicalDeviceProperties2::default()
        .push_next(&mut driver)
        .push_next(&mut p11)
        .push_next(&mut p13);
    if mesh_ext {
        props = props.push_next(&mut pmesh);
    }
    unsafe { instance.get_physical_device_properties2(pd, &mut props) };
    let text = |r: Result<&std::ffi::CStr, _>| {
        r.map(|s: &std::ffi::CStr| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    info.driver_name = text(driver.driver_name_as_c_str());
    info.driver_info = text(driver.driver_info_as_c_str());
    info.driver_id = driver.driver_id;
    info.is_cpu = looks_like_cpu(info.kind, driver.driver_id, &info.name);
    info.subgroup_size = p11.subgroup_size;
    info.min_subgroup_size = p13.min_subgroup_size;
    info.max_subgroup_size = p13.max_subgroup_size;
    info.compute_subgroup_ops = p11
        .subgroup_supported_stages
        .contains(vk::ShaderStageFlags::COMPUTE)
        && p11
            .subgroup_supported_operations
            .contains(REQUIRED_SUBGROUP_OPS);
    // Detached from the chain it was queried through.
    pmesh.p_next = std::ptr::null_mut();
    pmesh
}

/// The device's SMs or compute units, where a vendor extension tells
/// (querying an extension's properties needs it supported, not enabled).
fn compute_units(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    extensions: &[vk::ExtensionProperties],
) -> Option<u32> {
    let nv = has_extension(extensions, ash::nv::shader_sm_builtins::NAME);
    let amd = has_extension(extensions, ash::amd::shader_core_properties::NAME);
    let mut sm = vk::PhysicalDeviceShaderSMBuiltinsPropertiesNV::default();
    let mut core = vk::PhysicalDeviceShaderCorePropertiesAMD::default();
    let mut props = vk::PhysicalDeviceProperties2::default();
    if nv {
        props = props.push_next(&mut sm);
    }
    if amd {
        props = props.push_next(&mut core);
    }
    if !nv && !amd {
        return None;
    }
    unsafe { instance.get_physical_device_properties2(pd, &mut props) };
    let units = if nv {
        sm.shader_sm_count
    } else {
        core.shader_engine_count
            * core.shader_arrays_per_engine_count
            * core.compute_units_per_shader_array
    };
    (units > 0).then_some(units)
}

/// The optional features into `info`; returns the required ones missing.
fn read_features(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    (mesh_ext, prims_ext): (bool, bool),
    info: &mut DeviceInfo,
) -> Vec<String> {
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut fmesh = vk::PhysicalDeviceMeshShaderFeaturesEXT::default();
    let mut fprims = vk::PhysicalDevicePrimitivesGeneratedQueryFeaturesEXT::default();
    let mut feats = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut f12)
        .push_next(&mut f13);
    if mesh_ext {
        feats = feats.push_next(&mut fmesh);
    }
    if prims_ext {
        feats = feats.push_next(&mut fprims);
    }
    unsafe { instance.get_physical_device_features2(pd, &mut feats) };
    let f10 = feats.features;
    let on = |b: vk::Bool32| b == vk::TRUE;
    info.features = OptionalFeatures {
        mesh_shader: mesh_ext && on(fmesh.task_shader) && on(fmesh.mesh_shader),
        multi_draw_indirect: on(f10.multi_draw_indirect),
        draw_indirect_count: on(f12.draw_indirect_count),
        draw_indirect_first_instance: on(f10.draw_indirect_first_instance),
        vertex_pipeline_stores_and_atomics: on(f10.vertex_pipeline_stores_and_atomics),
        fragment_stores_and_atomics: on(f10.fragment_stores_and_atomics),
        shader_int64: on(f10.shader_int64),
        subgroup_size_control: on(f13.subgroup_size_control),
        compute_full_subgroups: on(f13.compute_full_subgroups),
        pipeline_statistics_query: on(f10.pipeline_statistics_query),
        tessellation_shader: on(f10.tessellation_shader),
        geometry_shader: on(f10.geometry_shader),
        primitives_generated_query: prims_ext && on(fprims.primitives_generated_query),
        mesh_shader_queries: mesh_ext && on(fmesh.mesh_shader_queries),
        vulkan_memory_model: on(f12.vulkan_memory_model)
            && on(f12.vulkan_memory_model_device_scope),
    };
    [
        (f13.synchronization2, "synchronization2"),
        (f13.dynamic_rendering, "dynamicRendering"),
        (f13.maintenance4, "maintenance4"),
    ]
    .into_iter()
    .filter(|(ok, _)| *ok == vk::FALSE)
    .map(|(_, what)| format!("feature `{what}` missing"))
    .collect()
}

fn mesh_info(p: &vk::PhysicalDeviceMeshShaderPropertiesEXT<'_>) -> MeshShaderInfo {
    MeshShaderInfo {
        max_mesh_output_vertices: p.max_mesh_output_vertices,
        max_mesh_output_primitives: p.max_mesh_output_primitives,
        max_mesh_work_group_invocations: p.max_mesh_work_group_invocations,
        max_task_work_group_invocations: p.max_task_work_group_invocations,
        max_task_work_group_count: p.max_task_work_group_count,
        max_task_work_group_total_count: p.max_task_work_group_total_count,
        max_task_payload_size: p.max_task_payload_size,
        max_preferred_mesh_work_group_invocations: p.max_preferred_mesh_work_group_invocations,
        max_preferred_task_work_group_invocations: p.max_preferred_task_work_group_invocations,
    }
}

fn limits_from(l: &vk::PhysicalDeviceLimits) -> DeviceLimits {
    DeviceLimits {
        max_compute_work_group_invocations: l.max_compute_work_group_invocations,
        max_compute_work_group_size: l.max_compute_work_group_size,
        max_compute_work_group_count: l.max_compute_work_group_count,
        max_compute_shared_memory_size: l.max_compute_shared_memory_size,
        max_storage_buffer_range: l.max_storage_buffer_range,
        max_uniform_buffer_range: l.max_uniform_buffer_range,
        max_push_constants_size: l.max_push_constants_size,
        min_storage_buffer_offset_alignment: l.min_storage_buffer_offset_alignment,
        min_uniform_buffer_offset_alignment: l.min_uniform_buffer_offset_alignment,
        max_draw_indirect_count: l.max_draw_indirect_count,
        max_tessellation_generation_level: l.max_tessellation_generation_level,
        framebuffer_sample_counts: l.framebuffer_color_sample_counts
            & l.framebuffer_depth_sample_counts,
    }
}

/// Picks the device `selector` names, checking it can run the renderer.
pub(crate) fn choose(
    candidates: &[Candidate],
    selector: &DeviceSelector,
    require_mesh_shader: bool,
) -> VkResult<usize> {
    let chosen = match selector {
        DeviceSelector::Auto => {
            let usable = |c: &&Candidate| {
                c.problems.is_empty() && (!require_mesh_shader || c.info.features.mesh_shader)
            };
            // Stable by enumeration order within a kind; CPU devices last
            // even when the driver reports them as "other".
            let rank = |c: &&Candidate| (c.info.is_cpu, c.info.kind, c.info.index);
            return candidates
                .iter()
                .filter(usable)
                .min_by_key(rank)
                .map(|c| c.info.index)
                .ok_or_else(|| VkError::NoSuitableDevice {
                    devices: format!(
                        "{}{}",
                        device_list(candidates),
                        if require_mesh_shader {
                            "\n(mesh shaders were required: VK_EXT_mesh_shader with taskShader and meshShader)"
                        } else {
                            ""
                        }
                    ),
                });
        }
        DeviceSelector::Index(i) => candidates.get(*i),
        DeviceSelector::Name(n) => {
            let needle = n.to_lowercase();
            candidates
                .iter()
                .find(|c| c.info.name.to_lowercase().contains(&needle))
        }
    };
    let Some(c) = chosen else {
        return Err(VkError::NoDeviceMatches {
            selector: selector.to_string(),
            devices: device_list(candidates),
        });
    };
    if let Some(problem) = c.problems.first() {
        return Err(VkError::FeatureMissing {
            device: c.info.name.clone(),
            feature: problem.clone(),
            hint: String::from("; pick another device with --device"),
        });
    }
    if require_mesh_shader && !c.info.features.mesh_shader {
        return Err(VkError::FeatureMissing {
            device: c.info.name.clone(),
            feature: String::from(
                "mesh shaders (VK_EXT_mesh_shader with taskShader and meshShader)",
            ),
            hint: String::from(
                "; use a method without mesh shaders (the compute fallback) or another device",
            ),
        });
    }
    Ok(c.info.index)
}

/// Marks the candidates whose queue family cannot present to `surface` as
/// unusable.
pub(crate) fn require_present(
    candidates: &mut [Candidate],
    loader: &ash::khr::surface::Instance,
    surface: vk::SurfaceKHR,
) {
    for c in candidates.iter_mut().filter(|c| c.problems.is_empty()) {
        let ok = unsafe {
            loader.get_physical_device_surface_support(c.handle, c.info.queue_family, surface)
        }
        .unwrap_or(false);
        if !ok {
            c.problems.push(String::from(
                "its graphics queue cannot present to the window",
            ));
        }
    }
}

/// Creates the logical device with the required features plus every
/// optional feature the candidate has (and VK_KHR_swapchain when it is to
/// present), and returns its single queue.
pub(crate) fn create_device(
    instance: &ash::Instance,
    c: &Candidate,
    present: bool,
) -> VkResult<(ash::Device, vk::Queue)> {
    let f = &c.info.features;

    let core = vk::PhysicalDeviceFeatures::default()
        .multi_draw_indirect(f.multi_draw_indirect)
        .draw_indirect_first_instance(f.draw_indirect_first_instance)
        .vertex_pipeline_stores_and_atomics(f.vertex_pipeline_stores_and_atomics)
        .fragment_stores_and_atomics(f.fragment_stores_and_atomics)
        .shader_int64(f.shader_int64)
        .pipeline_statistics_query(f.pipeline_statistics_query)
        .tessellation_shader(f.tessellation_shader)
        .geometry_shader(f.geometry_shader);
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default()
        .draw_indirect_count(f.draw_indirect_count)
        .vulkan_memory_model(f.vulkan_memory_model)
        .vulkan_memory_model_device_scope(f.vulkan_memory_model);
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default()
        .synchronization2(true)
        .dynamic_rendering(true)
        // glslc's Vulkan 1.3 SPIR-V relies on maintenance4 (LocalSizeId and
        // friends); the validation layer rejects the modules without it.
        .maintenance4(true)
        .subgroup_size_control(f.subgroup_size_control)
        .compute_full_subgroups(f.compute_full_subgroups);
    let mut fmesh = vk::PhysicalDeviceMeshShaderFeaturesEXT::default()
        .task_shader(true)
        .mesh_shader(true)
        .mesh_shader_queries(f.mesh_shader_queries);
    let mut fprims = vk::PhysicalDevicePrimitivesGeneratedQueryFeaturesEXT::default()
        .primitives_generated_query(true);

    let mut extensions: Vec<*const std::ffi::c_char> = Vec::new();
    if f.mesh_shader {
        extensions.push(ash::ext::mesh_shader::NAME.as_ptr());
    }
    if present {
        extensions.push(ash::khr::swapchain::NAME.as_ptr());
    }
    if f.primitives_generated_query {
        extensions.push(ash::ext::transform_feedback::NAME.as_ptr());
        extensions.push(ash::ext::primitives_generated_query::NAME.as_ptr());
    }

    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(c.info.queue_family)
        .queue_priorities(&priorities)];
    let mut features2 = vk::PhysicalDeviceFeatures2::default()
        .features(core)
        .push_next(&mut f12)
        .push_next(&mut f13);
    if f.mesh_shader {
        features2 = features2.push_next(&mut fmesh);
    }
    if f.primitives_generated_query {
        features2 = features2.push_next(&mut fprims);
    }
    let create = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&extensions)
        .push_next(&mut features2);
    let device = unsafe { instance.create_device(c.handle, &create, None) }
        .ctx(&format!("vkCreateDevice({})", c.info.name))?;
    let queue = unsafe { device.get_device_queue(c.info.queue_family, 0) };
    Ok((device, queue))
}
