//! GPU queries of a frame slot: timestamps with named scopes
//! ([`GpuTimer`]) and the primitives a frame's draws generate
//! ([`PrimitiveCounter`]).
//!
//! Usage: `reset` at the start of a command buffer, `begin`/`end` around the
//! work, and `read` after that command buffer's fence was waited on.

use super::context::{Context, Core};
use super::error::{VkError, VkResult, VkResultExt};
use super::frames::MAX_FRAME_PARTS;
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

    /// Writes the start timestamp of scope `name`. A name may come back
    /// once its previous scope has ended (a pass recorded once per part of
    /// a frame): [`GpuTimer::read`] sums its scopes.
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
        if self.scopes.iter().any(|(n, ended)| n == name && !ended) {
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

    /// Durations in milliseconds per scope name (the sum of its scopes), in
    /// first-begin order. Call only after the fences of the recording
    /// command buffers were waited on.
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
        let mut out: Vec<(String, f64)> = Vec::new();
        for (i, (name, _)) in self.scopes.iter().enumerate() {
            let start = ticks[2 * i] & self.valid_mask;
            let end = ticks[2 * i + 1] & self.valid_mask;
            // Masked wrapping difference: correct across one counter wrap.
            let delta = end.wrapping_sub(start) & self.valid_mask;
            let ms = delta as f64 * self.period_ns / 1.0e6;
            match out.iter_mut().find(|(n, _)| n == name) {
                Some((_, sum)) => *sum += ms,
                None => out.push((name.clone(), ms)),
            }
        }
        Ok(out)
    }
}

impl Drop for GpuTimer {
    fn drop(&mut self) {
        if !self.core.may_free() {
            return;
        }
        unsafe { self.core.device.destroy_query_pool(self.pool, None) };
    }
}

/// The query a [`PrimitiveCounter`] counts a frame with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrimitiveQuery {
    /// VK_EXT_primitives_generated_query: primitives leaving the last
    /// vertex-processing stage (vertex or tessellation evaluation) of
    /// vertex pipelines.
    Generated,
    /// VK_EXT_mesh_shader's mesh-primitives query: primitives a mesh shader
    /// emits (those it culls with `gl_CullPrimitiveEXT` are not counted).
    MeshGenerated,
    /// The pipeline-statistics query's clipping invocations: primitives
    /// reaching the clipper, where the extension is missing.
    ClippingInvocations,
}

impl PrimitiveQuery {
    /// How the stats name the source of a triangle count.
    pub fn name(self) -> &'static str {
        match self {
            Self::Generated => "primitives-generated query",
            Self::MeshGenerated => "mesh-primitives query",
            Self::ClippingInvocations => "clipping-invocations query",
        }
    }

    fn query_type(self) -> vk::QueryType {
        match self {
            Self::Generated => vk::QueryType::PRIMITIVES_GENERATED_EXT,
            Self::MeshGenerated => vk::QueryType::MESH_PRIMITIVES_GENERATED_EXT,
            Self::ClippingInvocations => vk::QueryType::PIPELINE_STATISTICS,
        }
    }
}

/// Counts the primitives a frame's draws generate, so every method's
/// triangle count means the same thing: what the rasterizer is handed.
///
/// One kind of query per frame, chosen by the kind of pipeline the frame
/// draws with (mesh pipelines need their own query type; lavapipe counts a
/// mesh draw in both the mesh and the generic query, so both at once would
/// count it twice). A query must begin and end in one command buffer, so a
/// frame recorded in parts counts each part in its own query
/// ([`PrimitiveCounter::next_part`]) and [`PrimitiveCounter::read`] sums
/// them. Compute work inside the query is not counted.
pub struct PrimitiveCounter {
    core: Arc<Core>,
    /// The device's queries, one pool each, one query per frame part.
    pools: Vec<(PrimitiveQuery, vk::QueryPool)>,
    /// The query kind begun this frame, the queries used (parts), and
    /// whether the last one ended.
    active: Option<(PrimitiveQuery, u32, bool)>,
}

impl PrimitiveCounter {
    /// The queries the device offers (possibly none: then frames report the
    /// methods' own counts).
    pub fn new(ctx: &Context) -> VkResult<Self> {
        let f = ctx.info().features;
        let available = [
            (PrimitiveQuery::Generated, f.primitives_generated_query),
            (PrimitiveQuery::MeshGenerated, f.mesh_shader_queries),
            (
                PrimitiveQuery::ClippingInvocations,
                f.pipeline_statistics_query,
            ),
        ];
        let mut counter = Self {
            core: ctx.core.clone(),
            pools: Vec::new(),
            active: None,
        };
        for (query, _) in available.into_iter().filter(|(_, on)| *on) {
            let mut create = vk::QueryPoolCreateInfo::default()
                .query_type(query.query_type())
                .query_count(MAX_FRAME_PARTS);
            if query == PrimitiveQuery::ClippingInvocations {
                create = create
                    .pipeline_statistics(vk::QueryPipelineStatisticFlags::CLIPPING_INVOCATIONS);
            }
            let pool = unsafe { ctx.device().create_query_pool(&create, None) }
                .ctx("vkCreateQueryPool(primitives)")?;
            ctx.set_name(pool, &format!("PrimitiveCounter ({})", query.name()));
            // Pushed at once so that Drop destroys it if a later one fails.
            counter.pools.push((query, pool));
        }
        Ok(counter)
    }

    /// The query a frame drawn with mesh pipelines (`mesh`) or vertex
    /// pipelines is counted with, if the device has one.
    pub fn choice(&self, mesh: bool) -> Option<PrimitiveQuery> {
        let has = |q| self.pools.iter().any(|(p, _)| *p == q);
        let order: &[PrimitiveQuery] = if mesh {
            // Lavapipe counts no clipping invocations for mesh draws, so
            // the statistics query is no stand-in there.
            &[PrimitiveQuery::MeshGenerated]
        } else {
            &[
                PrimitiveQuery::Generated,
                PrimitiveQuery::ClippingInvocations,
            ]
        };
        order.iter().copied().find(|&q| has(q))
    }

    fn pool(&self, query: PrimitiveQuery) -> Option<vk::QueryPool> {
        self.pools
            .iter()
            .find(|(q, _)| *q == query)
            .map(|(_, p)| *p)
    }

    /// Resets the queries in `cmd` (outside any render pass) and forgets
    /// the previous frame's choice. Call before [`PrimitiveCounter::begin`].
    pub fn reset(&mut self, cmd: vk::CommandBuffer) {
        for &(_, pool) in &self.pools {
            unsafe {
                self.core
                    .device
                    .cmd_reset_query_pool(cmd, pool, 0, MAX_FRAME_PARTS)
            };
        }
        self.active = None;
    }

    /// Begins counting a frame drawn with mesh pipelines (`mesh`) or vertex
    /// pipelines; without a suitable query nothing is recorded.
    pub fn begin(&mut self, cmd: vk::CommandBuffer, mesh: bool) -> VkResult<()> {
        if self.active.is_some() {
            return Err(VkError::Usage(
                "PrimitiveCounter begun twice in one frame".into(),
            ));
        }
        let Some(query) = self.choice(mesh) else {
            return Ok(());
        };
        if let Some(pool) = self.pool(query) {
            unsafe {
                self.core
                    .device
                    .cmd_begin_query(cmd, pool, 0, vk::QueryControlFlags::empty())
            };
            self.active = Some((query, 1, false));
        }
        Ok(())
    }

    /// Ends the current part's query in `cmd` (that part's last command
    /// buffer, outside any render pass); [`PrimitiveCounter::resume`] begins
    /// the next part's.
    pub fn pause(&mut self, cmd: vk::CommandBuffer) -> VkResult<()> {
        match self.active {
            None => Ok(()),
            Some((_, _, true)) => Err(VkError::Usage("PrimitiveCounter already ended".into())),
            Some((query, used, false)) => {
                if used >= MAX_FRAME_PARTS {
                    return Err(VkError::Usage(format!(
                        "PrimitiveCounter counts at most {MAX_FRAME_PARTS} parts"
                    )));
                }
                if let Some(pool) = self.pool(query) {
                    unsafe { self.core.device.cmd_end_query(cmd, pool, used - 1) };
                }
                self.active = Some((query, used, true));
                Ok(())
            }
        }
    }

    /// Begins the next part's query in `cmd` (its first command buffer)
    /// after a [`PrimitiveCounter::pause`].
    pub fn resume(&mut self, cmd: vk::CommandBuffer) -> VkResult<()> {
        match self.active {
            None => Ok(()),
            Some((_, _, false)) => Err(VkError::Usage("PrimitiveCounter is not paused".into())),
            Some((query, used, true)) => {
                if let Some(pool) = self.pool(query) {
                    unsafe {
                        self.core.device.cmd_begin_query(
                            cmd,
                            pool,
                            used,
                            vk::QueryControlFlags::empty(),
                        )
                    };
                }
                self.active = Some((query, used + 1, false));
                Ok(())
            }
        }
    }

    /// Ends counting (outside any render pass).
    pub fn end(&mut self, cmd: vk::CommandBuffer) -> VkResult<()> {
        match self.active {
            None => Ok(()),
            Some((_, _, true)) => Err(VkError::Usage("PrimitiveCounter ended twice".into())),
            Some((query, used, false)) => {
                if let Some(pool) = self.pool(query) {
                    unsafe { self.core.device.cmd_end_query(cmd, pool, used - 1) };
                }
                self.active = Some((query, used, true));
                Ok(())
            }
        }
    }

    /// The count (summed over the frame's parts) and the query it came
    /// from, or `None` when the frame was not counted. Call only after the
    /// recording command buffers' fences were waited on.
    pub fn read(&self) -> VkResult<Option<(PrimitiveQuery, u64)>> {
        let Some((query, used, ended)) = self.active else {
            return Ok(None);
        };
        if !ended {
            return Err(VkError::Usage("PrimitiveCounter was never ended".into()));
        }
        let Some(pool) = self.pool(query) else {
            return Ok(None);
        };
        // Every query type here has exactly one 64-bit result (the
        // statistics pool counts one statistic).
        let mut counts = vec![0u64; used as usize];
        unsafe {
            self.core.device.get_query_pool_results(
                pool,
                0,
                &mut counts,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .ctx("vkGetQueryPoolResults(primitives)")?;
        Ok(Some((query, counts.iter().sum())))
    }
}

impl Drop for PrimitiveCounter {
    fn drop(&mut self) {
        if !self.core.may_free() {
            return;
        }
        for &(_, pool) in &self.pools {
            unsafe { self.core.device.destroy_query_pool(pool, None) };
        }
    }
}
