//! The Vulkan layer's error type: every failure carries enough context for a
//! user to act on it without a debugger.

use ash::vk;
use std::path::PathBuf;
use std::time::Duration;

/// The environment variable that sets the fence timeout in seconds (the
/// `--timeout` flag wins over it).
pub const TIMEOUT_ENV: &str = "BEZIER_SUBDIV_TIMEOUT";

/// A duration as a person reads it: "850 ms", "42 s", "2 min 4 s".
pub fn seconds_text(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s < 1.0 {
        format!("{:.0} ms", s * 1000.0)
    } else if s < 60.0 {
        format!("{:.0} s", s)
    } else {
        let whole = s.round() as u64;
        format!("{} min {} s", whole / 60, whole % 60)
    }
}

/// Result alias for the Vulkan layer.
pub type VkResult<T> = Result<T, VkError>;

/// Everything that can go wrong in `crate::vk`.
#[derive(Debug, thiserror::Error)]
pub enum VkError {
    /// A Vulkan call returned an error code.
    #[error("{context} failed: {result}")]
    Call {
        /// What was being attempted, e.g. "vkCreateDevice".
        context: String,
        /// The code the driver returned.
        result: vk::Result,
    },

    /// The Vulkan loader library could not be opened.
    #[error(
        "the Vulkan loader (libvulkan) could not be loaded: {0}; \
         install it (Debian: `apt install libvulkan1 mesa-vulkan-drivers`)"
    )]
    LoaderMissing(String),

    /// The loader or instance is older than the API version we need.
    #[error("the Vulkan loader supports API {found}, but bezier-subdiv needs Vulkan 1.3 or newer")]
    LoaderTooOld {
        /// The instance version the loader reported, as "major.minor.patch".
        found: String,
    },

    /// No physical device met the requirements.
    #[error("no suitable Vulkan device found; devices seen:\n{devices}")]
    NoSuitableDevice {
        /// One line per enumerated device with the reason it was rejected.
        devices: String,
    },

    /// `--device` named an index or substring that matched nothing.
    #[error("no Vulkan device matches `{selector}`; available devices:\n{devices}")]
    NoDeviceMatches {
        /// The selector as the user wrote it.
        selector: String,
        /// One line per enumerated device.
        devices: String,
    },

    /// The chosen device lacks something we cannot run without.
    #[error("device `{device}` does not support {feature}, which bezier-subdiv requires{hint}")]
    FeatureMissing {
        /// The device's name.
        device: String,
        /// The missing feature, extension or API version, in words.
        feature: String,
        /// Extra advice (starts with "; " when non-empty).
        hint: String,
    },

    /// A setting the user asked for that the device does not offer (the
    /// run can go on with another value).
    #[error("device `{device}` does not offer {what}{hint}")]
    NotOffered {
        /// The device's name.
        device: String,
        /// What was asked for, in words.
        what: String,
        /// What it does offer, and where to look (starts with "; ").
        hint: String,
    },

    /// The validation layer was requested but is not installed.
    #[error(
        "validation was requested but the layer `VK_LAYER_KHRONOS_validation` is not installed; \
         install the Debian package `vulkan-validationlayers` or run without validation"
    )]
    ValidationLayerMissing,

    /// gpu-allocator failed to create itself or an allocation. The
    /// allocator's words are part of the message, not an error source, so
    /// that error chains (`{:#}`) print them once.
    #[error("memory allocation for `{name}` failed: {cause}")]
    Allocation {
        /// The resource the memory was for.
        name: String,
        /// The allocator's error.
        cause: gpu_allocator::AllocationError,
    },

    /// A fence did not signal in time: the device is slow or busy, or the
    /// work hangs. The message says what ran, for how long, and what to try.
    #[error(
        "{label}{} did not finish within the {} fence timeout{} ({} since it was submitted). \
         A slow or busy device (a CPU device such as lavapipe, or one shared with other work) \
         may only need longer: pass --timeout SECONDS or set {TIMEOUT_ENV}=SECONDS. Or ask for \
         less work per frame: a smaller --size, and for ground-truth a coarser --grid (16 draws \
         1/16 of the triangles of the default 64). On an idle, fast device the work more likely \
         hangs (e.g. a persistent-threads loop that never exits)",
        part.map_or(String::new(), |(k, n)| format!(" (part {k} of {n})")),
        seconds_text(*timeout),
        if allowance.is_zero() {
            String::new()
        } else {
            format!(
                " and the {} allowed beyond it for compiling shaders on their first use",
                seconds_text(*allowance)
            )
        },
        seconds_text(*waited)
    )]
    FenceTimeout {
        /// What was submitted.
        label: String,
        /// How long one wait may take.
        timeout: Duration,
        /// And beyond that for compiling pipelines run for the first time.
        allowance: Duration,
        /// How long it had been running (since its submission) when given up.
        waited: Duration,
        /// Which part of a frame submitted in parts (1-based, of how many).
        part: Option<(u32, u32)>,
    },

    /// The device was lost (driver reset, crash or hang).
    #[error("the Vulkan device was lost while waiting for `{label}`")]
    DeviceLost {
        /// What was running.
        label: String,
    },

    /// The validation layer reported errors.
    #[error("the validation layer reported {count} error(s):\n{}", messages.join("\n"))]
    Validation {
        /// Total number of errors since the last check.
        count: u64,
        /// The first few messages (the rest are counted only).
        messages: Vec<String>,
    },

    /// A SPIR-V file is missing or malformed.
    #[error(
        "SPIR-V `{path}`: {reason}; regenerate the shaders with \
         `cargo run --release -p compile-shaders`"
    )]
    Spirv {
        /// The file (or label for embedded bytes).
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },

    /// A request needs a buffer larger than one storage-buffer binding of
    /// this device may be: refused before anything is allocated, with what
    /// the user can change.
    #[error(
        "the {what} needs {bytes} bytes, more than this device's storage-buffer range of \
         {limit} bytes ({hint})"
    )]
    OverDeviceLimit {
        /// What would not fit (e.g. "fallback vertex buffer for 2097152 ready nodes").
        what: String,
        /// What it needs.
        bytes: u64,
        /// `maxStorageBufferRange`.
        limit: u64,
        /// What to change.
        hint: &'static str,
    },

    /// The API was used in a way it does not support (a programming error
    /// reported as an error rather than a panic).
    #[error("invalid use of the Vulkan layer: {0}")]
    Usage(String),
}

/// Attaches a context string to a raw `vk::Result` error.
pub(crate) trait VkResultExt<T> {
    /// Wraps the error in [`VkError::Call`] with `context`.
    fn ctx(self, context: &str) -> VkResult<T>;
}

impl<T> VkResultExt<T> for Result<T, vk::Result> {
    fn ctx(self, context: &str) -> VkResult<T> {
        self.map_err(|result| VkError::Call {
            context: context.to_owned(),
            result,
        })
    }
}
