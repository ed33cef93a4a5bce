//! The validation layer and VK_EXT_debug_utils: enabling them, counting what
//! they report, and naming objects so their messages say which buffer is meant.

use super::error::{VkError, VkResult, VkResultExt};
use ash::vk;
use std::ffi::{c_void, CStr, CString};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// The Khronos validation layer's name.
pub const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How many error messages are kept verbatim between checks; the rest are
/// only counted, so a test that floods the layer cannot exhaust memory.
const KEPT_MESSAGES: usize = 32;

/// Counters and the first messages the debug messenger has seen.
///
/// The driver calls back on whatever thread made the Vulkan call, so
/// everything here is atomic or locked.
#[derive(Debug, Default)]
pub struct DebugState {
    errors: AtomicU64,
    warnings: AtomicU64,
    messages: Mutex<Vec<String>>,
}

impl DebugState {
    /// Errors reported since the last [`DebugState::take_errors`].
    pub fn error_count(&self) -> u64 {
        self.errors.load(Ordering::SeqCst)
    }

    /// Warnings reported since the messenger was created.
    pub fn warning_count(&self) -> u64 {
        self.warnings.load(Ordering::SeqCst)
    }

    /// The first kept error messages since the last take, without clearing.
    pub fn error_messages(&self) -> Vec<String> {
        self.messages
            .lock()
            .map(|m| m.clone())
            .unwrap_or_else(|e| e.into_inner().clone())
    }

    /// Returns the error count and kept messages, and starts counting afresh.
    pub fn take_errors(&self) -> (u64, Vec<String>) {
        let mut kept = self.messages.lock().unwrap_or_else(|e| e.into_inner());
        let count = self.errors.swap(0, Ordering::SeqCst);
        (count, std::mem::take(&mut *kept))
    }

    fn record(&self, severity: vk::DebugUtilsMessageSeverityFlagsEXT, text: &str) {
        if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            self.errors.fetch_add(1, Ordering::SeqCst);
            if let Ok(mut kept) = self.messages.lock() {
                if kept.len() < KEPT_MESSAGES {
                    kept.push(text.to_owned());
                }
            }
        } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
            self.warnings.fetch_add(1, Ordering::SeqCst);
        }
    }
}

/// The messenger callback: logs through `log` and counts into [`DebugState`].
///
/// It must never unwind into the driver, so it only does things that cannot
/// panic (lossy string conversion, non-panicking locks).
unsafe extern "system" fn messenger_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    let text = if data.is_null() {
        String::from("(no message)")
    } else {
        (*data)
            .message_as_c_str()
            .map(|m| m.to_string_lossy().into_owned())
            .unwrap_or_else(|| String::from("(no message)"))
    };
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        log::error!(target: "vulkan", "[{types:?}] {text}");
    } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
        log::warn!(target: "vulkan", "[{types:?}] {text}");
    } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::INFO) {
        log::debug!(target: "vulkan", "[{types:?}] {text}");
    } else {
        log::trace!(target: "vulkan", "[{types:?}] {text}");
    }
    if let Some(state) = (user as *const DebugState).as_ref() {
        state.record(severity, &text);
    }
    // VK_FALSE: never abort the call that triggered the message.
    vk::FALSE
}

/// Create-info for a messenger reporting into `state`.
///
/// The same struct is chained into `VkInstanceCreateInfo` so messages from
/// instance creation and destruction are caught too; `state` must therefore
/// outlive the instance.
pub(crate) fn messenger_info(state: &DebugState) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    let mut severity = vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
        | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING;
    // The loader's INFO chatter is only worth the callbacks when it is shown.
    if log::log_enabled!(target: "vulkan", log::Level::Debug) {
        severity |= vk::DebugUtilsMessageSeverityFlagsEXT::INFO;
    }
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(severity)
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(messenger_callback))
        .user_data(state as *const DebugState as *mut c_void)
}

/// Which instance layers and extensions the debug setup needs.
pub(crate) struct DebugSupport {
    /// VK_EXT_debug_utils is offered by the loader or a layer.
    pub debug_utils: bool,
    /// VK_EXT_validation_features is offered by the validation layer.
    pub validation_features: bool,
}

/// Checks for the validation layer (when wanted) and debug utils.
pub(crate) fn probe(entry: &ash::Entry, validation: bool) -> VkResult<DebugSupport> {
    let has_ext = |list: &[vk::ExtensionProperties], name: &CStr| {
        list.iter()
            .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name))
    };
    let instance_exts = unsafe { entry.enumerate_instance_extension_properties(None) }
        .ctx("vkEnumerateInstanceExtensionProperties")?;
    let mut support = DebugSupport {
        debug_utils: has_ext(&instance_exts, ash::ext::debug_utils::NAME),
        validation_features: false,
    };
    if validation {
        let layers = unsafe { entry.enumerate_instance_layer_properties() }
            .ctx("vkEnumerateInstanceLayerProperties")?;
        let found = layers
            .iter()
            .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER));
        if !found {
            return Err(VkError::ValidationLayerMissing);
        }
        let layer_exts =
            unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
                .ctx("vkEnumerateInstanceExtensionProperties(validation layer)")?;
        support.debug_utils |= has_ext(&layer_exts, ash::ext::debug_utils::NAME);
        support.validation_features = has_ext(&layer_exts, ash::ext::validation_features::NAME);
    }
    Ok(support)
}

/// Gives `handle` a name that validation messages and capture tools show.
///
/// Naming is best effort: without debug utils it does nothing, and a failure
/// to name is logged rather than returned because nothing depends on it.
pub(crate) fn set_name<H: vk::Handle>(
    loader: Option<&ash::ext::debug_utils::Device>,
    handle: H,
    name: &str,
) {
    let Some(loader) = loader else { return };
    let name = CString::new(name.replace('\0', " ")).unwrap_or_default();
    let info = vk::DebugUtilsObjectNameInfoEXT::default()
        .object_handle(handle)
        .object_name(&name);
    if let Err(e) = unsafe { loader.set_debug_utils_object_name(&info) } {
        log::debug!("vkSetDebugUtilsObjectNameEXT({name:?}) failed: {e}");
    }
}
