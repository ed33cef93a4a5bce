//! The Vulkan context: instance, device, queue, allocator and command pool,
//! plus the validation bookkeeping tests check.
//!
//! Ownership: the handles every resource needs (device, allocator) live in a
//! reference-counted `Core`. Buffers, images, pipelines hold an `Arc<Core>`
//! and free themselves on drop, so nothing can outlive the device and
//! nothing needs a context passed to its destructor. The device is destroyed
//! when the last holder goes.

use super::debug::{self, DebugState, VALIDATION_LAYER};
use super::device::{self, DeviceSelector};
use super::error::{VkError, VkResult, VkResultExt, TIMEOUT_ENV};
use super::info::{version_string, DeviceInfo};
use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::{AllocationSizes, AllocatorDebugSettings};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

/// Fence waits give up after this long unless told otherwise (the
/// `--timeout` flag, [`TIMEOUT_ENV`]). Long work is submitted in parts
/// (`FrameRec::split`), so the limit applies to a part, not to a frame.
pub const DEFAULT_FENCE_TIMEOUT: Duration = Duration::from_secs(60);

/// What a submission that runs a pipeline for the first time may take
/// beyond its fence timeout on a device that compiles pipelines when they
/// first run ([`Context::take_compile_allowance`]): on this project's
/// 2-core machine lavapipe compiles the kitchen's first `subdiv` frame in
/// about 30 s (the persistent kernel alone took 77 s before its pipelines
/// were specialized for the scene); ten minutes leave room for a loaded
/// machine and a slower one.
pub const COMPILE_ALLOWANCE: Duration = Duration::from_secs(600);

/// The process-wide fence timeout set by [`set_fence_timeout`], in ns (0:
/// none set).
static TIMEOUT_OVERRIDE_NS: AtomicU64 = AtomicU64::new(0);

/// Set once any device was leaked because its work never finished.
static DEVICE_LEAKED: AtomicBool = AtomicBool::new(false);

/// Whether this process leaked a device whose work may still run. Its
/// driver may then still execute on its own threads (lavapipe does), and
/// the process's exit handlers unloading the driver under them crash it:
/// such a process should end without running them (`_exit`).
pub fn device_leaked() -> bool {
    DEVICE_LEAKED.load(Ordering::SeqCst)
}

/// Sets the fence timeout every later [`ContextOptions::default`] takes
/// (the command line's `--timeout`; it wins over [`TIMEOUT_ENV`]).
pub fn set_fence_timeout(timeout: Duration) {
    let ns = u64::try_from(timeout.as_nanos()).unwrap_or(u64::MAX).max(1);
    TIMEOUT_OVERRIDE_NS.store(ns, Ordering::SeqCst);
}

/// Parses a timeout in seconds ("300", "2.5"): positive and finite.
pub fn parse_timeout(s: &str) -> Result<Duration, String> {
    let secs: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number of seconds"))?;
    if !(secs.is_finite() && secs > 0.0 && secs < 1.0e9) {
        return Err(format!(
            "the timeout must be a positive number of seconds (got {s})"
        ));
    }
    Ok(Duration::from_secs_f64(secs))
}

/// The fence timeout [`TIMEOUT_ENV`] asks for: `None` when unset, an error
/// naming the variable when it is not a positive number of seconds.
pub fn env_fence_timeout() -> Result<Option<Duration>, String> {
    match std::env::var(TIMEOUT_ENV) {
        Err(_) => Ok(None),
        Ok(v) => parse_timeout(&v)
            .map(Some)
            .map_err(|e| format!("{TIMEOUT_ENV}: {e}")),
    }
}

/// The fence timeout a context gets by default: [`set_fence_timeout`]'s,
/// else [`TIMEOUT_ENV`]'s (a bad value is logged and ignored; the command
/// line refuses it before any work), else [`DEFAULT_FENCE_TIMEOUT`].
pub fn default_fence_timeout() -> Duration {
    let ns = TIMEOUT_OVERRIDE_NS.load(Ordering::SeqCst);
    if ns > 0 {
        return Duration::from_nanos(ns);
    }
    match env_fence_timeout() {
        Ok(Some(t)) => t,
        Ok(None) => DEFAULT_FENCE_TIMEOUT,
        Err(e) => {
            log::warn!("{e}; using {DEFAULT_FENCE_TIMEOUT:?}");
            DEFAULT_FENCE_TIMEOUT
        }
    }
}

/// How to create a [`Context`].
#[derive(Debug, Clone)]
pub struct ContextOptions {
    /// Which device to use.
    pub selector: DeviceSelector,
    /// Enable the Khronos validation layer and count its messages.
    pub validation: bool,
    /// With validation: also enable synchronization validation (missing or
    /// wrong barriers), if the layer offers VK_EXT_validation_features.
    pub sync_validation: bool,
    /// Fail device selection unless task + mesh shaders are available.
    pub require_mesh_shader: bool,
    /// Default timeout for fence waits (a hung shader must fail, not stall).
    pub fence_timeout: Duration,
    /// Present to this window: the surface extensions are enabled, the
    /// chosen device must be able to present to it, and the context owns
    /// the surface (the window must outlive the context).
    pub window: Option<WindowHandles>,
    /// What a submission that runs a pipeline for the first time may wait
    /// beyond its fence timeout on a device that compiles pipelines when
    /// they first run ([`COMPILE_ALLOWANCE`]; tests of the timeout itself
    /// set zero).
    pub compile_allowance: Duration,
    /// Told (once per wait) when a submission waits for the driver to
    /// compile pipelines on their first use for more than a few seconds
    /// (the command line prints it; a library user may leave it `None`).
    pub notice: Option<fn(&str)>,
}

/// A window's raw handles, for [`ContextOptions::window`].
#[derive(Debug, Clone, Copy)]
pub struct WindowHandles {
    /// The display connection.
    pub display: raw_window_handle::RawDisplayHandle,
    /// The window.
    pub window: raw_window_handle::RawWindowHandle,
}

impl Default for ContextOptions {
    fn default() -> Self {
        Self {
            selector: DeviceSelector::Auto,
            validation: false,
            sync_validation: true,
            require_mesh_shader: false,
            fence_timeout: default_fence_timeout(),
            window: None,
            compile_allowance: COMPILE_ALLOWANCE,
            notice: None,
        }
    }
}

/// Handles shared by the context and every resource created from it.
pub(crate) struct Core {
    /// Kept only so the loader library stays loaded while the instance lives.
    entry: ManuallyDrop<ash::Entry>,
    pub(crate) instance: ash::Instance,
    pub(crate) physical_device: vk::PhysicalDevice,
    pub(crate) device: ash::Device,
    pub(crate) allocator: ManuallyDrop<Mutex<Allocator>>,
    pub(crate) debug_utils: Option<ash::ext::debug_utils::Device>,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// The window surface, destroyed before the instance.
    pub(crate) surface: Option<(ash::khr::surface::Instance, vk::SurfaceKHR)>,
    /// Its address is the messenger's user data, so it lives until after
    /// the instance is destroyed (see `Drop`); tests may hold a clone to
    /// see messages from device and instance destruction.
    debug_state: ManuallyDrop<Arc<DebugState>>,
    /// Set when submitted work never finished: tearing down would block
    /// forever in vkDeviceWaitIdle or free memory the GPU still uses.
    pub(crate) hung: AtomicBool,
    /// Fences of one-shot submissions whose wait timed out (with the
    /// timeout they were given), until the context reclaims them. A
    /// resource dropped meanwhile may be one they use (an upload's
    /// destination), so [`Core::may_free`] waits for them first.
    pub(crate) unfinished: Mutex<Vec<(vk::Fence, Duration)>>,
    /// Pipelines bound for the first time since the last submission took
    /// them ([`Context::take_compile_allowance`]).
    pub(crate) first_uses: AtomicU32,
    /// The driver compiles a pipeline when it first runs (a CPU device),
    /// not when it is made.
    pub(crate) compiles_at_first_use: bool,
    /// See [`ContextOptions::compile_allowance`].
    compile_allowance: Duration,
    /// See [`ContextOptions::notice`].
    notice: Option<fn(&str)>,
}

/// How long a wait that may include a first-use compile runs before the
/// user is told that shaders are compiling.
const COMPILE_NOTICE_AFTER: Duration = Duration::from_secs(3);

impl Core {
    /// Waits for `fence` (what `label` submitted) up to `timeout` plus the
    /// compile `allowance` ([`Context::take_compile_allowance`]); a wait
    /// with an allowance that lasts past [`COMPILE_NOTICE_AFTER`] tells the
    /// user that shaders are compiling, unless `noticed` says an earlier
    /// part of the same submission did (which this sets when it tells).
    pub(crate) fn wait_fence(
        &self,
        fence: vk::Fence,
        timeout: Duration,
        allowance: Duration,
        label: &str,
        noticed: &mut bool,
    ) -> Result<(), vk::Result> {
        let wait =
            |d: Duration| unsafe { self.device.wait_for_fences(&[fence], true, duration_ns(d)) };
        let total = timeout + allowance;
        let Some(notice) = self.notice.filter(|_| !allowance.is_zero() && !*noticed) else {
            return wait(total);
        };
        match wait(COMPILE_NOTICE_AFTER.min(total)) {
            Err(vk::Result::TIMEOUT) if total > COMPILE_NOTICE_AFTER => {}
            done => return done,
        }
        *noticed = true;
        notice(&format!(
            "compiling shaders for {label} on their first use on this device (a CPU driver \
             compiles them when they first run, seconds to a minute; the driver caches them \
             for later runs)"
        ));
        wait(total - COMPILE_NOTICE_AFTER)
    }

    /// Locks the allocator; a poisoned lock is still usable because the
    /// allocator's state is updated atomically with respect to panics.
    pub(crate) fn allocator(&self) -> MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Names an object for validation messages (no-op without debug utils).
    pub(crate) fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        debug::set_name(self.debug_utils.as_ref(), handle, name);
    }
}

impl Core {
    /// Whether a resource may be destroyed now: not while the device is
    /// hung, and not while a timed-out one-shot submission may still use it.
    /// Those are waited for (each as long as its own timeout); one that
    /// still does not finish marks the device hung, so nothing is freed
    /// under the GPU (lavapipe writes into freed memory and crashes).
    pub(crate) fn may_free(&self) -> bool {
        if self.hung.load(Ordering::SeqCst) {
            return false;
        }
        let unfinished = self.unfinished.lock().unwrap_or_else(|e| e.into_inner());
        if unfinished.is_empty() {
            return true;
        }
        let fences: Vec<vk::Fence> = unfinished.iter().map(|&(f, _)| f).collect();
        let timeout = unfinished.iter().map(|&(_, t)| t).max().unwrap_or_default();
        let done = unsafe {
            self.device
                .wait_for_fences(&fences, true, duration_ns(timeout))
        };
        if done.is_err() {
            log::error!("timed-out Vulkan work still runs; leaking what it may use");
            self.hung.store(true, Ordering::SeqCst);
        }
        done.is_ok()
    }

    /// Forgets a timed-out submission's fence before it is destroyed.
    pub(crate) fn forget_unfinished(&self, fence: vk::Fence) {
        let mut unfinished = self.unfinished.lock().unwrap_or_else(|e| e.into_inner());
        unfinished.retain(|&(f, _)| f != fence);
    }
}

impl Drop for Core {
    fn drop(&mut self) {
        if self.hung.load(Ordering::SeqCst) {
            // The GPU may still run our work and the driver may still call
            // the messenger: leak everything rather than hang or crash.
            log::error!("Vulkan work never finished; leaking the device instead of destroying it");
            DEVICE_LEAKED.store(true, Ordering::SeqCst);
            return;
        }
        unsafe {
            let _ = self.device.device_wait_idle();
            // The allocator frees its memory blocks through the device.
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((loader, surface)) = self.surface.take() {
                loader.destroy_surface(surface, None);
            }
            if let Some((loader, messenger)) = self.messenger.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            // Messages from instance destruction still reach `debug_state`
            // through the chained create-info, so it is freed only after.
            self.instance.destroy_instance(None);
            ManuallyDrop::drop(&mut self.debug_state);
            ManuallyDrop::drop(&mut self.entry);
        }
    }
}

/// A command buffer whose fence wait timed out, kept until it finishes.
pub(crate) struct Pending {
    pub label: String,
    pub fence: vk::Fence,
    pub cmd: vk::CommandBuffer,
    /// Resources the command buffer uses (e.g. a staging buffer), kept
    /// whatever their type until it ends.
    pub keep_alive: Vec<Box<dyn std::any::Any + Send>>,
    /// When it was submitted (for the timeout's message).
    pub submitted: std::time::Instant,
}

/// The command pool and queue, which Vulkan requires to be externally
/// synchronised, with the timed-out submissions still in flight.
pub(crate) struct SubmitState {
    pub pool: vk::CommandPool,
    pub pending: Vec<Pending>,
}

/// The Vulkan context: one device, one queue, an allocator and a command pool.
pub struct Context {
    pub(crate) core: Arc<Core>,
    pub(crate) queue: vk::Queue,
    pub(crate) submit: Mutex<SubmitState>,
    pub(crate) fence_timeout: Duration,
    mesh: Option<ash::ext::mesh_shader::Device>,
    swapchain: Option<ash::khr::swapchain::Device>,
    info: DeviceInfo,
    validation: bool,
    all_devices: String,
}

impl Context {
    /// Creates a context on the device `options.selector` picks.
    pub fn new(options: &ContextOptions) -> VkResult<Self> {
        let entry = load_entry()?;
        let support = debug::probe(&entry, options.validation)?;
        let debug_state = Arc::new(DebugState::default());
        let instance = create_instance(&entry, options, &support, &debug_state)?;
        // From here on, failures must destroy what was made; `Partial`
        // does that on drop unless disarmed.
        let mut partial = Partial {
            instance: Some(instance.clone()),
            messenger: None,
            surface: None,
            device: None,
        };
        if options.validation && support.debug_utils {
            let loader = ash::ext::debug_utils::Instance::new(&entry, &instance);
            let info = debug::messenger_info(&debug_state);
            let messenger = unsafe { loader.create_debug_utils_messenger(&info, None) }
                .ctx("vkCreateDebugUtilsMessengerEXT")?;
            partial.messenger = Some((loader, messenger));
        }

        if let Some(w) = options.window {
            let surface =
                unsafe { ash_window::create_surface(&entry, &instance, w.display, w.window, None) }
                    .ctx("creating the window surface")?;
            partial.surface = Some((ash::khr::surface::Instance::new(&entry, &instance), surface));
        }
        let mut candidates = device::enumerate(&instance)?;
        if let Some((loader, surface)) = &partial.surface {
            device::require_present(&mut candidates, loader, *surface);
        }
        let all_devices = device::device_list(&candidates);
        let chosen = device::choose(&candidates, &options.selector, options.require_mesh_shader)?;
        let candidate = &candidates[chosen];
        let (device, queue) =
            device::create_device(&instance, candidate, options.window.is_some())?;
        partial.device = Some(device.clone());
        let info = enabled_info(candidate, options.validation);
        let allocator = create_allocator(&instance, &device, candidate.handle)?;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(info.queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT);
        let pool =
            unsafe { device.create_command_pool(&pool_info, None) }.ctx("vkCreateCommandPool")?;

        let debug_utils = support
            .debug_utils
            .then(|| ash::ext::debug_utils::Device::new(&instance, &device));
        let mesh = info
            .features
            .mesh_shader
            .then(|| ash::ext::mesh_shader::Device::new(&instance, &device));
        let swapchain = options
            .window
            .map(|_| ash::khr::swapchain::Device::new(&instance, &device));
        let messenger = partial.messenger.take();
        let surface = partial.surface.take();
        partial.disarm();
        let core = Arc::new(Core {
            entry: ManuallyDrop::new(entry),
            instance,
            physical_device: candidate.handle,
            device,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            debug_utils,
            messenger,
            surface,
            debug_state: ManuallyDrop::new(debug_state),
            hung: AtomicBool::new(false),
            unfinished: Mutex::new(Vec::new()),
            first_uses: AtomicU32::new(0),
            compiles_at_first_use: info.is_cpu,
            compile_allowance: options.compile_allowance,
            notice: options.notice,
        });
        core.set_name(pool, "one-shot command pool");
        Ok(Self {
            core,
            queue,
            submit: Mutex::new(SubmitState {
                pool,
                pending: Vec::new(),
            }),
            fence_timeout: options.fence_timeout,
            mesh,
            swapchain,
            info,
            validation: options.validation,
            all_devices,
        })
    }

    /// The window surface and its functions, for contexts made with
    /// [`ContextOptions::window`].
    pub fn surface(&self) -> Option<(&ash::khr::surface::Instance, vk::SurfaceKHR)> {
        self.core.surface.as_ref().map(|(l, s)| (l, *s))
    }

    /// VK_KHR_swapchain functions, for contexts made with a window.
    pub fn swapchain_loader(&self) -> Option<&ash::khr::swapchain::Device> {
        self.swapchain.as_ref()
    }

    /// Every Vulkan device found, one line each (index, name, kind).
    pub fn all_devices(&self) -> &str {
        &self.all_devices
    }

    /// Identity, limits and enabled features of the device.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// The logical device, for recording commands.
    pub fn device(&self) -> &ash::Device {
        &self.core.device
    }

    /// The instance.
    pub fn instance(&self) -> &ash::Instance {
        &self.core.instance
    }

    /// The physical device.
    pub fn physical_device(&self) -> vk::PhysicalDevice {
        self.core.physical_device
    }

    /// The queue. Submitting to it outside [`Context::with_queue`] while
    /// another thread runs a one-shot breaks Vulkan's external sync rules.
    pub fn queue(&self) -> vk::Queue {
        self.queue
    }

    /// Runs `f` with exclusive access to the queue.
    pub fn with_queue<R>(&self, f: impl FnOnce(vk::Queue) -> R) -> R {
        let _guard = self.lock_submit();
        f(self.queue)
    }

    /// VK_EXT_mesh_shader entry points, if mesh shaders are enabled.
    pub fn mesh_shader(&self) -> Option<&ash::ext::mesh_shader::Device> {
        self.mesh.as_ref()
    }

    /// The debug-utils device functions (object names, labels), if enabled.
    pub fn debug_utils(&self) -> Option<&ash::ext::debug_utils::Device> {
        self.core.debug_utils.as_ref()
    }

    /// Names a Vulkan object so validation messages mention it.
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        self.core.set_name(handle, name);
    }

    /// Whether the validation layer is on.
    pub fn validation_enabled(&self) -> bool {
        self.validation
    }

    /// The default fence timeout.
    pub fn fence_timeout(&self) -> Duration {
        self.fence_timeout
    }

    /// The time a submission recorded since the last call may take beyond
    /// its fence timeout for compiling shaders: the context's allowance
    /// ([`ContextOptions::compile_allowance`], by default [`COMPILE_ALLOWANCE`]) where
    /// it binds a pipeline for the first time on a device that compiles
    /// pipelines when they first run (lavapipe compiles inside the
    /// submission, on the CPU, for seconds to minutes), else nothing. So a
    /// cold compile on a busy machine is never taken for a hang, and the
    /// timeout still bounds the work itself.
    pub fn take_compile_allowance(&self) -> Duration {
        let first = self.core.first_uses.swap(0, Ordering::SeqCst);
        if first > 0 && self.core.compiles_at_first_use {
            self.core.compile_allowance
        } else {
            Duration::ZERO
        }
    }

    /// Changes the default fence timeout.
    pub fn set_fence_timeout(&mut self, timeout: Duration) {
        self.fence_timeout = timeout;
    }

    /// The first validation error messages since the last check (not cleared).
    pub fn validation_errors(&self) -> Vec<String> {
        self.core.debug_state.error_messages()
    }

    /// Validation errors since the last check, including ones not kept verbatim.
    pub fn validation_error_count(&self) -> u64 {
        self.core.debug_state.error_count()
    }

    /// Validation warnings since the context was created.
    pub fn validation_warning_count(&self) -> u64 {
        self.core.debug_state.warning_count()
    }

    /// The validation message counters; outlives the context, so a test can
    /// check what destroying the device reported (e.g. leaked objects).
    pub fn debug_state(&self) -> Arc<DebugState> {
        Arc::clone(&self.core.debug_state)
    }

    /// Number of live gpu-allocator allocations (for leak tests).
    pub fn live_allocations(&self) -> usize {
        self.core.allocator().generate_report().allocations.len()
    }

    /// Fails if the validation layer reported any error since the last
    /// check, and starts counting afresh either way.
    pub fn check_validation(&self) -> VkResult<()> {
        let (count, messages) = self.core.debug_state.take_errors();
        if count == 0 {
            Ok(())
        } else {
            Err(VkError::Validation { count, messages })
        }
    }

    /// Declares the device's submitted work unfinishable (a fence wait timed
    /// out for good, or the device was lost): from now on nothing is
    /// destroyed or freed, since the GPU may still use it, and the device is
    /// leaked at teardown instead of waited for.
    pub fn mark_hung(&self) {
        self.core.hung.store(true, Ordering::SeqCst);
    }

    /// Whether [`Context::mark_hung`] was called (or a wait found the device
    /// lost).
    pub fn is_hung(&self) -> bool {
        self.core.hung.load(Ordering::SeqCst)
    }

    pub(crate) fn lock_submit(&self) -> MutexGuard<'_, SubmitState> {
        self.submit.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        let timeout = self.fence_timeout;
        let state = self.submit.get_mut().unwrap_or_else(|e| e.into_inner());
        let device = &self.core.device;
        let mut finished = true;
        for p in state.pending.drain(..) {
            let done = unsafe { device.wait_for_fences(&[p.fence], true, duration_ns(timeout)) };
            if done.is_ok() {
                self.core.forget_unfinished(p.fence);
                unsafe {
                    device.destroy_fence(p.fence, None);
                    device.free_command_buffers(state.pool, &[p.cmd]);
                }
            } else {
                log::error!("`{}` still running at shutdown", p.label);
                finished = false;
                // Its resources must not be freed under the GPU.
                std::mem::forget(p.keep_alive);
            }
        }
        if finished {
            unsafe { device.destroy_command_pool(state.pool, None) };
        } else {
            self.core.hung.store(true, Ordering::SeqCst);
        }
    }
}

/// Loads the Vulkan loader and checks it speaks Vulkan 1.3.
fn load_entry() -> VkResult<ash::Entry> {
    let entry = unsafe { ash::Entry::load() }.map_err(|e| VkError::LoaderMissing(e.to_string()))?;
    let loader_version = unsafe { entry.try_enumerate_instance_version() }
        .ctx("vkEnumerateInstanceVersion")?
        .unwrap_or(vk::API_VERSION_1_0);
    if loader_version < vk::API_VERSION_1_3 {
        return Err(VkError::LoaderTooOld {
            found: version_string(loader_version),
        });
    }
    Ok(entry)
}

/// The instance: Vulkan 1.3, with the validation layer (and its messenger
/// chained, so instance creation itself is reported) when asked, and
/// synchronization validation where the layer offers it.
fn create_instance(
    entry: &ash::Entry,
    options: &ContextOptions,
    support: &debug::DebugSupport,
    debug_state: &Arc<DebugState>,
) -> VkResult<ash::Instance> {
    let app_info = vk::ApplicationInfo::default()
        .application_name(c"bezier-subdiv")
        .application_version(vk::make_api_version(0, 0, 1, 0))
        .engine_name(c"bezier-subdiv")
        .api_version(vk::API_VERSION_1_3);
    let layers = if options.validation {
        vec![VALIDATION_LAYER.as_ptr()]
    } else {
        Vec::new()
    };
    let mut extensions = Vec::new();
    if support.debug_utils {
        extensions.push(ash::ext::debug_utils::NAME.as_ptr());
    }
    if let Some(w) = options.window {
        let needed = ash_window::enumerate_required_extensions(w.display)
            .ctx("the window system's Vulkan surface extensions")?;
        extensions.extend_from_slice(needed);
    }
    let want_sync = options.validation && options.sync_validation;
    if want_sync && support.validation_features {
        extensions.push(ash::ext::validation_features::NAME.as_ptr());
    } else if want_sync {
        log::warn!("the validation layer lacks VK_EXT_validation_features; synchronization validation is off");
    }
    let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
    let mut chained_messenger = debug::messenger_info(debug_state);
    let mut create = vk::InstanceCreateInfo::default()
        .application_info(&app_info)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    if options.validation && support.debug_utils {
        create = create.push_next(&mut chained_messenger);
    }
    if want_sync && support.validation_features {
        create = create.push_next(&mut features);
    }
    match unsafe { entry.create_instance(&create, None) } {
        Ok(instance) => Ok(instance),
        Err(vk::Result::ERROR_INCOMPATIBLE_DRIVER) => Err(VkError::NoSuitableDevice {
            devices: String::from(
                "  (none: the Vulkan loader found no driver; install your GPU's Vulkan \
                 driver, or `mesa-vulkan-drivers` for the lavapipe CPU device)",
            ),
        }),
        Err(vk::Result::ERROR_LAYER_NOT_PRESENT) => Err(VkError::ValidationLayerMissing),
        Err(result) => Err(VkError::Call {
            context: String::from("vkCreateInstance"),
            result,
        }),
    }
}

/// The chosen device's description as enabled (a device without mesh
/// shaders reports no mesh limits either), logged.
fn enabled_info(candidate: &device::Candidate, validation: bool) -> DeviceInfo {
    let mut info = candidate.info.clone();
    if !info.features.mesh_shader {
        info.mesh = None;
    }
    log::info!(
        "Vulkan device {}: {} ({}, driver {} {}, Vulkan {}){}",
        info.index,
        info.name,
        info.kind_label(),
        info.driver_name,
        info.driver_info,
        info.api_version_string(),
        if validation { ", validation on" } else { "" }
    );
    info
}

/// The memory allocator. Small first blocks: tests make many tiny buffers
/// and lavapipe backs "device memory" with host RAM.
fn create_allocator(
    instance: &ash::Instance,
    device: &ash::Device,
    physical_device: vk::PhysicalDevice,
) -> VkResult<Allocator> {
    Allocator::new(&AllocatorCreateDesc {
        instance: instance.clone(),
        device: device.clone(),
        physical_device,
        debug_settings: AllocatorDebugSettings::default(),
        buffer_device_address: false,
        allocation_sizes: AllocationSizes::new(16 << 20, 16 << 20)
            .with_max_device_memblock_size(256 << 20)
            .with_max_host_memblock_size(256 << 20),
    })
    .map_err(|cause| VkError::Allocation {
        name: String::from("allocator"),
        cause,
    })
}

/// A timeout as Vulkan's nanosecond count, saturating.
pub(crate) fn duration_ns(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

/// Objects created during `Context::new` before `Core` owns them; destroyed
/// in reverse order if creation fails half way.
struct Partial {
    instance: Option<ash::Instance>,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    surface: Option<(ash::khr::surface::Instance, vk::SurfaceKHR)>,
    device: Option<ash::Device>,
}

impl Partial {
    fn disarm(&mut self) {
        self.instance = None;
        self.messenger = None;
        self.surface = None;
        self.device = None;
    }
}

impl Drop for Partial {
    fn drop(&mut self) {
        unsafe {
            if let Some(device) = self.device.take() {
                device.destroy_device(None);
            }
            if let Some((loader, surface)) = self.surface.take() {
                loader.destroy_surface(surface, None);
            }
            if let Some((loader, messenger)) = self.messenger.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            if let Some(instance) = self.instance.take() {
                instance.destroy_instance(None);
            }
        }
    }
}
