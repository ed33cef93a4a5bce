//! GPU timestamps with named scopes.
//!
//! Usage: `reset` at the start of a command buffer, `begin`/`end` around the
//! work, and `read` after that command buffer's fence was waited on.

use super::context::{Context, Core};
use super::error::{VkError, VkResult, VkResultExt};
use ash::vk;
use std::sync::Arc;

/// A query pool of timestamp pairs, one pair per named scope.
pub struct GpuTimer {
    core: Arc<Core>,
    pool: vk::QueryPool,
    capacity: u32,
    /// Scope names in begin order, with whether `end` was recorded.
    scopes: Vec<(String, bool)>,
    period_ns: f64,
    valid_mask: u64,
}

impl GpuTimer {
    /// A timer with room for `max_scopes` scopes per command buffer.
    pub fn new(ctx: &Context, max_scopes: u32) -> VkResult<Self> {
        let info = ctx.info();
        if info.timestamp_valid_bits == 0 {
            return Err(VkError::FeatureMissing {
                device: info.name.clone(),
                feature: format!("timestamps on queue family {}", info.queue_family),
                hint: String::from("; GPU timings are unavailable on this device"),
            });
        }
        if max_scopes == 0 {
            return Err(VkError::Usage(String::from(
                "GpuTimer needs at least one scope",
            )));
        }
        let create = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(2 * max_scopes);
        let pool = unsafe { ctx.device().create_query_pool(&create, None) }
            .ctx("vkCreateQueryPool(timestamps)")?;
        ctx.set_name(pool, "GpuTimer timestamps");
        let valid_mask = if info.timestamp_valid_bits >= 64 {
            u64::MAX
        } else {
            (1u64 << info.timestamp_valid_bits) - 1
        };
        Ok(Self {
            core: ctx.core.clone(),
            pool,
            capacity: max_scopes,
            scopes: Vec::new(),
            period_ns: f64::from(info.timestamp_period),
            valid_mask,
        })
    }

    /// Resets all queries in `cmd` (outside any render pass) and forgets the
    /// previous scopes. Call before the first `begin` of a command buffer.
    pub fn reset(&mut self, cmd: vk::CommandBuffer) {
        unsafe {
            self.core
                .device
                .cmd_reset_query_pool(cmd, self.pool, 0, 2 * self.capacity)
        };
        self.scopes.clear();
    }

    /// Writes the start timestamp of scope `name`.
    ///
    /// ALL_COMMANDS waits for earlier work, so a scope measures its own
    /// commands rather than overlapping the previous ones.
    pub fn begin(&mut self, cmd: vk::CommandBuffer, name: &str) -> VkResult<()> {
        if self.scopes.len() as u32 >= self.capacity {
            return Err(VkError::Usage(format!(
                "GpuTimer holds {} scopes; `{name}` is one too many",
                self.capacity
            )));
        }
        if self.scopes.iter().any(|(n, _)| n == name) {
            return Err(VkError::Usage(format!(
                "GpuTimer scope `{name}` begun twice"
            )));
        }
        let query = 2 * self.scopes.len() as u32;
        self.scopes.push((name.to_owned(), false));
        unsafe {
            self.core.device.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                query,
            )
        };
        Ok(())
    }

    /// Writes the end timestamp of scope `name` once all work so far is done.
    pub fn end(&mut self, cmd: vk::CommandBuffer, name: &str) -> VkResult<()> {
        let index = self
            .scopes
            .iter()
            .position(|(n, ended)| n == name && !ended)
            .ok_or_else(|| VkError::Usage(format!("GpuTimer scope `{name}` ended but not open")))?;
        self.scopes[index].1 = true;
        unsafe {
            self.core.device.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                2 * index as u32 + 1,
            )
        };
        Ok(())
    }

    /// Durations in milliseconds per scope, in begin order. Call only after
    /// the fence of the recording command buffer was waited on.
    pub fn read(&self) -> VkResult<Vec<(String, f64)>> {
        if let Some((name, _)) = self.scopes.iter().find(|(_, ended)| !ended) {
            return Err(VkError::Usage(format!(
                "GpuTimer scope `{name}` was never ended"
            )));
        }
        if self.scopes.is_empty() {
            return Ok(Vec::new());
        }
        let mut ticks = vec![0u64; 2 * self.scopes.len()];
        // WAIT cannot block for long here: the caller waited on the fence.
        unsafe {
            self.core.device.get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .ctx("vkGetQueryPoolResults(timestamps)")?;
        Ok(self
            .scopes
            .iter()
            .enumerate()
            .map(|(i, (name, _))| {
                let start = ticks[2 * i] & self.valid_mask;
                let end = ticks[2 * i + 1] & self.valid_mask;
                // Masked wrapping difference: correct across one counter wrap.
                let delta = end.wrapping_sub(start) & self.valid_mask;
                (name.clone(), delta as f64 * self.period_ns / 1.0e6)
            })
            .collect())
    }
}

impl Drop for GpuTimer {
    fn drop(&mut self) {
        if self.core.hung.load(std::sync::atomic::Ordering::SeqCst) {
            return;
        }
        unsafe { self.core.device.destroy_query_pool(self.pool, None) };
    }
}
