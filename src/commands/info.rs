//! `info`: the Vulkan devices found and the one `--device auto` picks.

use crate::vk::{describe, Context, ContextOptions};

/// The text `info` prints.
pub fn run(validation: bool) -> anyhow::Result<String> {
    let ctx = Context::new(&ContextOptions {
        validation,
        ..ContextOptions::default()
    })?;
    let info = ctx.info();
    Ok(format!(
        "Vulkan devices (pick one with --device INDEX or --device NAME):\n{}\n\n\
         --device auto picks #{}: {}{}\n\n{}\n",
        ctx.all_devices(),
        info.index,
        info.name,
        if info.is_cpu {
            " (a CPU device: correct, but slow)"
        } else {
            ""
        },
        describe(info)
    ))
}
