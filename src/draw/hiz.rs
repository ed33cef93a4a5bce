//! The depth pyramid occlusion culling tests against (issue 22): built
//! between the two phases of a frame from the depth the early phase drew
//! (`glsl/hiz_init*.comp`, `glsl/hiz_reduce.comp`), read by the level
//! kernels' late phase (`glsl/common/hiz.glsl`).
//!
//! Level 0 holds every pixel's farthest depth sample; level k + 1 the
//! farthest of the 2 × 2 texels of level k it covers (sizes rounded up),
//! down to 1 × 1, all in one storage buffer of floats, so a texel of level
//! k is never nearer than any pixel it covers. A box whose nearest depth
//! lies beyond the texels its pixel rectangle touches cannot win a depth
//! test anywhere: culling it changes no pixel.

use ash::vk;

use crate::constants::{BIND_HIZ_DEPTH, BIND_HIZ_PYRAMID, HIZ_BINDINGS, HIZ_GROUP, SET_PASS};
use crate::frame::{FrameRec, Retired};
use crate::gpu::{DrawTarget, HizPush, SceneLayout, Shaders};
use crate::vk::{
    Access, Binding, Buffer, Context, DescriptorSet, MemoryLocation, Pass, Pipeline,
    PipelineLayout, Recorder, Res, Sampler, SetLayout, VkResult,
};

/// The levels of a `width` × `height` pyramid: (first float, width,
/// height) each, level 0 first, down to 1 × 1.
pub fn pyramid_levels(width: u32, height: u32) -> Vec<(u32, u32, u32)> {
    let (mut w, mut h, mut offset) = (width.max(1), height.max(1), 0);
    let mut levels = vec![(0, w, h)];
    while w > 1 || h > 1 {
        offset += w * h;
        w = w.div_ceil(2);
        h = h.div_ceil(2);
        levels.push((offset, w, h));
    }
    levels
}

/// Floats of a `width` × `height` pyramid.
pub fn pyramid_floats(width: u32, height: u32) -> u64 {
    pyramid_levels(width, height)
        .iter()
        .map(|&(_, w, h)| u64::from(w) * u64::from(h))
        .sum()
}

/// The pyramid for the current draw target, its set and its passes.
pub struct Hiz {
    set_layout: SetLayout,
    layout: PipelineLayout<HizPush>,
    init: Pipeline,
    init_ms: Pipeline,
    reduce: Pipeline,
    sampler: Sampler,
    pyramid: Option<Pyramid>,
}

/// A pyramid buffer and the set that reads one depth image into it.
struct Pyramid {
    buffer: Buffer,
    set: DescriptorSet,
    size: (u32, u32),
    depth: vk::ImageView,
}

/// The depth-pyramid passes' shaders, which share set 1.
pub const HIZ_SHADERS: &[&str] = &["hiz_init.comp", "hiz_init_ms.comp", "hiz_reduce.comp"];

impl Hiz {
    /// The passes' layout, pipelines and sampler (the pyramid is made for
    /// the first target it is built from).
    pub fn new(ctx: &Context, shaders: &mut Shaders, scene: &SceneLayout) -> VkResult<Self> {
        let set_layout = SetLayout::reflect(ctx, "depth pyramid set", SET_PASS, HIZ_SHADERS)?;
        let layout = scene.pipeline_layout::<HizPush>(
            ctx,
            "depth pyramid layout",
            &[&set_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        Ok(Self {
            init: shaders.compute(ctx, &layout, "depth pyramid level 0", "hiz_init.comp")?,
            init_ms: shaders.compute(
                ctx,
                &layout,
                "depth pyramid level 0 (multisampled)",
                "hiz_init_ms.comp",
            )?,
            reduce: shaders.compute(ctx, &layout, "depth pyramid level", "hiz_reduce.comp")?,
            sampler: Sampler::nearest(ctx, "depth pyramid sampler")?,
            set_layout,
            layout,
            pyramid: None,
        })
    }

    /// The pyramid buffer for `target` (made, the old one retired, when
    /// the target's size or depth image changed); true when it is new.
    pub fn ensure(
        &mut self,
        ctx: &Context,
        target: &DrawTarget,
        retired: &mut Retired,
    ) -> VkResult<bool> {
        let size = target.size();
        let depth = target.depth().view();
        if self
            .pyramid
            .as_ref()
            .is_some_and(|p| p.size == size && p.depth == depth)
        {
            return Ok(false);
        }
        let buffer = Buffer::new(
            ctx,
            "depth pyramid",
            4 * pyramid_floats(size.0, size.1),
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let mut bound = [Binding::from(&buffer); HIZ_BINDINGS as usize];
        bound[BIND_HIZ_DEPTH as usize] = Binding::Image {
            view: depth,
            layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            sampler: &self.sampler,
        };
        bound[BIND_HIZ_PYRAMID as usize] = Binding::from(&buffer);
        let set = DescriptorSet::with_bindings(ctx, "depth pyramid set", &self.set_layout, &bound)?;
        if let Some(old) = self.pyramid.replace(Pyramid {
            buffer,
            set,
            size,
            depth,
        }) {
            retired.push(old.buffer);
            retired.push(old.set);
        }
        Ok(true)
    }

    /// The pyramid buffer, once made.
    pub fn buffer(&self) -> Option<&Buffer> {
        self.pyramid.as_ref().map(|p| &p.buffer)
    }

    /// Bytes of the pyramid.
    pub fn bytes(&self) -> u64 {
        self.buffer().map_or(0, Buffer::size)
    }

    /// Records building the pyramid from the depth the frame drew so far
    /// (scope "hiz"): the depth image to a sampled layout and back to an
    /// attachment (what it drew stays for the next part), one pass per
    /// level. Call after [`Hiz::ensure`] for the frame's target.
    pub fn record_build(&self, f: &mut FrameRec<'_>) -> VkResult<()> {
        let Some(p) = &self.pyramid else {
            return Err(crate::vk::VkError::Usage(
                "the depth pyramid was built before it was made".into(),
            ));
        };
        let depth = f.target.depth();
        let samples = f.target.samples().as_raw();
        f.scoped("hiz", |f| {
            let (ctx, cmd) = (f.ctx, f.cmd);
            let sampled = Access::new(
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_SAMPLED_READ,
            );
            let mut rec = Recorder::new(ctx, cmd);
            // What the frame drew so far, and the previous frame's late
            // phase, which read the pyramid.
            let attached = vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL;
            rec.after(Res::Image(depth, attached), Access::DEPTH_ATTACHMENT);
            rec.after(Res::Memory, Access::ALL);
            let read_depth = Res::Image(depth, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL);
            let levels = pyramid_levels(p.size.0, p.size.1);
            for (k, &(offset, w, h)) in levels.iter().enumerate() {
                let (src_offset, src_width, src_height) =
                    if k == 0 { (0, w, h) } else { levels[k - 1] };
                let pipeline = match (k, samples) {
                    (0, 1) => &self.init,
                    (0, _) => &self.init_ms,
                    _ => &self.reduce,
                };
                self.layout.push(
                    cmd,
                    &HizPush {
                        src_offset,
                        dst_offset: offset,
                        src_width,
                        src_height,
                        dst_width: w,
                        dst_height: h,
                        samples,
                        pad: 0,
                    },
                );
                // Each level reads the last: the pyramid buffer, which the
                // set it binds points at.
                let pass = Pass::new("hiz level").pipeline(pipeline).bind(1, &p.set);
                let mut pass = f.with_scene(pass);
                if k == 0 {
                    pass = pass.read(read_depth, sampled);
                }
                rec.dispatch(&pass, [w.div_ceil(HIZ_GROUP), h.div_ceil(HIZ_GROUP), 1]);
            }
            // The late phase tests against the pyramid; what it drew stays
            // in the depth image for the next part.
            rec.hand_off_set(&p.set, Access::COMPUTE_READ_WRITE);
            rec.hand_off(Res::Image(depth, attached), Access::DEPTH_ATTACHMENT);
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_halve_rounding_up_to_one_texel() {
        let l = pyramid_levels(5, 3);
        assert_eq!(l, vec![(0, 5, 3), (15, 3, 2), (21, 2, 1), (23, 1, 1)]);
        assert_eq!(pyramid_floats(5, 3), 24);
        assert_eq!(pyramid_levels(1, 1), vec![(0, 1, 1)]);
        // 1080p: 12 levels, 4/3 of the pixels plus what rounding up adds
        // (under a row and a column per level).
        let full = pyramid_levels(1920, 1080);
        assert_eq!(full.len(), 12);
        assert!(pyramid_floats(1920, 1080) < 1920 * 1080 * 4 / 3 + 1920 + 1080);
    }
}
