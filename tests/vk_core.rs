//! The Vulkan core on a real device (lavapipe in CI), validation on: every
//! test fails on any validation error.

mod common;

use ash::vk;
use bezier_subdiv::vk::{
    buffer_barrier, describe, fill_buffer, Access, Buffer, BufferBinding, Context, ContextOptions,
    DescriptorSet, DeviceSelector, GpuTimer, Image, ImageDesc, MemoryLocation, Pipeline,
    PipelineLayout, SetLayout, ShaderModule, VkError,
};
use std::path::Path;
use std::time::Duration;

const STORAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::STORAGE_BUFFER;

#[test]
fn context_reports_device_info() {
    let ctx = common::gpu();
    let info = ctx.info();
    assert!(!info.name.is_empty());
    assert!(
        info.api_version >= vk::API_VERSION_1_3,
        "{}",
        info.api_version_string()
    );
    assert!(info.limits.max_compute_work_group_invocations >= 128);
    assert!(info.limits.max_compute_shared_memory_size >= 16 * 1024);
    assert!(info.limits.max_storage_buffer_range > 0);
    assert!(info.subgroup_size > 0);
    assert!(info.timestamp_period > 0.0);
    assert_eq!(info.has_mesh_shader(), info.mesh.is_some());
    assert_eq!(info.has_mesh_shader(), ctx.mesh_shader().is_some());
    let text = describe(info);
    assert!(text.contains(&info.name), "{text}");
    if info.name.contains("llvmpipe") {
        // lavapipe: a CPU device with mesh shaders (LAVAPIPE.md).
        assert!(info.is_cpu);
        assert!(text.contains("CPU device"), "{text}");
        assert!(info.has_mesh_shader());
        let mesh = info.mesh.expect("mesh properties");
        assert!(mesh.max_mesh_output_vertices >= 256);
        assert!(mesh.max_mesh_output_primitives >= 256);
        assert!(info.features.tessellation_shader);
        assert!(info.features.multi_draw_indirect);
        assert_eq!(info.timestamp_valid_bits, 64);
    }
    println!("{text}");
    ctx.finish();
}

#[test]
fn device_selection_by_index_and_name() {
    let ctx = common::gpu();
    let shared = ctx.info().clone();
    let with = |selector| {
        Context::new(&ContextOptions {
            selector,
            ..common::test_options()
        })
    };

    let by_index = with(DeviceSelector::Index(shared.index)).expect("select by index");
    assert_eq!(by_index.info().name, shared.name);
    by_index.check_validation().expect("clean");
    drop(by_index);

    // Case-insensitive substring of the name.
    let needle: String = shared
        .name
        .chars()
        .take(6)
        .collect::<String>()
        .to_uppercase();
    let selector: DeviceSelector = needle.parse().unwrap();
    assert_eq!(selector, DeviceSelector::Name(needle.clone()));
    let by_name = with(selector).expect("select by name");
    assert_eq!(by_name.info().name, shared.name);
    by_name.check_validation().expect("clean");
    drop(by_name);

    match with(DeviceSelector::Name(String::from("no-such-device-xyz"))) {
        Err(e @ VkError::NoDeviceMatches { .. }) => {
            let msg = e.to_string();
            assert!(msg.contains("no-such-device-xyz"), "{msg}");
            assert!(msg.contains(&shared.name), "device list missing: {msg}");
        }
        Err(e) => panic!("wrong error: {e}"),
        Ok(c) => panic!("matched {}", c.info().name),
    }
    assert!(matches!(
        with(DeviceSelector::Index(9999)),
        Err(VkError::NoDeviceMatches { .. })
    ));
    ctx.finish();
}

#[test]
fn selector_parsing() {
    assert_eq!("auto".parse(), Ok(DeviceSelector::Auto));
    assert_eq!("".parse(), Ok(DeviceSelector::Auto));
    assert_eq!("2".parse(), Ok(DeviceSelector::Index(2)));
    assert_eq!(
        "llvmpipe".parse(),
        Ok(DeviceSelector::Name(String::from("llvmpipe")))
    );
}

#[test]
fn buffer_round_trips() {
    let ctx = common::gpu();
    let data: Vec<u32> = (0..1000u32)
        .map(|i| i.wrapping_mul(2_654_435_761))
        .collect();
    for location in [
        MemoryLocation::GpuOnly,
        MemoryLocation::CpuToGpu,
        MemoryLocation::GpuToCpu,
    ] {
        let mut buf = Buffer::with_data(&ctx, "round trip", &data, STORAGE, location).unwrap();
        assert_eq!(buf.read::<u32>(&ctx).unwrap(), data, "{location:?}");
        // A partial write at an offset leaves the rest alone.
        buf.write(&ctx, 8, &[7u32, 9]).unwrap();
        let back: Vec<u32> = buf.read(&ctx).unwrap();
        assert_eq!(&back[..2], &data[..2]);
        assert_eq!(&back[2..4], &[7, 9]);
        assert_eq!(&back[4..], &data[4..]);
        assert!(matches!(
            buf.write(&ctx, 3999, &[1u32]),
            Err(VkError::Usage(_))
        ));
    }
    assert!(matches!(
        Buffer::new(&ctx, "empty", 0, STORAGE, MemoryLocation::GpuOnly),
        Err(VkError::Usage(_))
    ));
    ctx.finish();
}

#[test]
fn one_shot_fill_and_copy() {
    let ctx = common::gpu();
    let a = Buffer::new(&ctx, "fill target", 256, STORAGE, MemoryLocation::GpuOnly).unwrap();
    let b = Buffer::with_data(
        &ctx,
        "copy target",
        &[0u32; 64],
        STORAGE,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    let value = ctx
        .one_shot(|cmd| {
            let d = ctx.device();
            unsafe { d.cmd_fill_buffer(cmd, a.handle(), 0, vk::WHOLE_SIZE, 0xDEAD_BEEF) };
            buffer_barrier(&ctx, cmd, &a, Access::TRANSFER_WRITE, Access::TRANSFER_READ);
            buffer_barrier(&ctx, cmd, &b, Access::ALL, Access::TRANSFER_WRITE);
            let region = [vk::BufferCopy::default()
                .src_offset(16)
                .dst_offset(32)
                .size(64)];
            unsafe { d.cmd_copy_buffer(cmd, a.handle(), b.handle(), &region) };
            Ok(42)
        })
        .unwrap();
    assert_eq!(value, 42, "one_shot returns the closure's value");
    let back: Vec<u32> = b.read(&ctx).unwrap();
    for (i, v) in back.iter().enumerate() {
        let want = if (8..24).contains(&i) { 0xDEAD_BEEF } else { 0 };
        assert_eq!(*v, want, "word {i}");
    }
    ctx.finish();
}

/// A recording closure that fails submits nothing: its commands never run
/// and its error comes back as is.
#[test]
fn failed_recording_submits_nothing() {
    let ctx = common::gpu();
    let a = Buffer::with_data(
        &ctx,
        "untouched",
        &[7u32; 16],
        STORAGE,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    let result: Result<(), VkError> = ctx.one_shot(|cmd| {
        buffer_barrier(&ctx, cmd, &a, Access::ALL, Access::TRANSFER_WRITE);
        unsafe {
            ctx.device()
                .cmd_fill_buffer(cmd, a.handle(), 0, vk::WHOLE_SIZE, 0)
        };
        Err(VkError::Usage("planted recording failure".into()))
    });
    let err = result.unwrap_err();
    assert!(
        err.to_string().contains("planted recording failure"),
        "{err}"
    );
    let back: Vec<u32> = a.read(&ctx).unwrap();
    assert_eq!(back, vec![7u32; 16], "the half-recorded fill ran");
    assert_eq!(ctx.pending_count(), 0);
    ctx.finish();
}

#[test]
fn image_clear_and_read_pixels() {
    let ctx = common::gpu();
    let image = Image::new(
        &ctx,
        &ImageDesc {
            name: "clear target",
            width: 7,
            height: 5,
            format: vk::Format::R8G8B8A8_UNORM,
            usage: vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::COLOR_ATTACHMENT,
            samples: vk::SampleCountFlags::TYPE_1,
        },
    )
    .unwrap();
    let layout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
    ctx.one_shot(|cmd| {
        bezier_subdiv::vk::image_barrier(
            &ctx,
            cmd,
            &image,
            vk::ImageLayout::UNDEFINED,
            layout,
            Access::NONE,
            Access::TRANSFER_WRITE,
        );
        let color = vk::ClearColorValue {
            float32: [1.0, 0.0, 1.0, 0.0],
        };
        unsafe {
            ctx.device().cmd_clear_color_image(
                cmd,
                image.handle(),
                layout,
                &color,
                &[image.full_range()],
            )
        };
        Ok(())
    })
    .unwrap();
    let pixels = image.read_pixels(&ctx, layout).unwrap();
    assert_eq!(pixels.len(), 7 * 5 * 4);
    assert!(pixels.chunks(4).all(|p| p == [255, 0, 255, 0]));
    ctx.finish();
}

/// The buffers and pipeline of `glsl/selftest.comp`.
struct SelfTest {
    pipeline: Pipeline,
    layout: PipelineLayout<[u32; 3]>,
    _set_layout: SetLayout,
    set: DescriptorSet,
    data: Buffer,
    counters: Buffer,
    _params: Buffer,
    count: u32,
}

const LOCAL_SIZE: u32 = 64;

impl SelfTest {
    fn new(ctx: &Context, count: u32) -> Self {
        let shader = ShaderModule::load(ctx, "selftest.comp").unwrap();
        let stage = vk::ShaderStageFlags::COMPUTE;
        let set_layout = SetLayout::reflect(ctx, "selftest set", 0, &["selftest.comp"]).unwrap();
        let layout = PipelineLayout::new(ctx, "selftest layout", &[&set_layout], stage).unwrap();
        let pipeline =
            Pipeline::compute(ctx, "selftest", &layout, &shader, &[(0, LOCAL_SIZE)]).unwrap();
        let data = Buffer::new(
            ctx,
            "selftest data",
            u64::from(count) * 4,
            STORAGE,
            MemoryLocation::GpuOnly,
        )
        .unwrap();
        let counters = Buffer::with_data(
            ctx,
            "selftest counters",
            &[0u32; 3],
            STORAGE,
            MemoryLocation::GpuOnly,
        )
        .unwrap();
        let params = Buffer::with_data(
            ctx,
            "selftest params",
            &[1u32, 0, 0, 0],
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )
        .unwrap();
        let bound: [BufferBinding; 3] = [(&data).into(), (&counters).into(), (&params).into()];
        let set = DescriptorSet::new(ctx, "selftest set", &set_layout, &bound).unwrap();
        Self {
            pipeline,
            layout,
            _set_layout: set_layout,
            set,
            data,
            counters,
            _params: params,
            count,
        }
    }

    fn record(&self, ctx: &Context, cmd: vk::CommandBuffer, mul: u32, spin: u32) {
        // Earlier uploads (other submissions) must land before the shader.
        buffer_barrier(
            ctx,
            cmd,
            &self.data,
            Access::ALL,
            Access::COMPUTE_READ_WRITE,
        );
        buffer_barrier(
            ctx,
            cmd,
            &self.counters,
            Access::ALL,
            Access::COMPUTE_READ_WRITE,
        );
        let push = [mul, self.count, spin];
        let groups = self.count.div_ceil(LOCAL_SIZE);
        self.pipeline.bind(cmd);
        self.set.bind(
            ctx,
            cmd,
            vk::PipelineBindPoint::COMPUTE,
            &self.layout,
            0,
            &[],
        );
        self.layout.push(cmd, &push);
        unsafe { ctx.device().cmd_dispatch(cmd, groups, 1, 1) };
    }

    fn check(&self, ctx: &Context, mul: u32) {
        let data: Vec<u32> = self.data.read(ctx).unwrap();
        for (i, v) in data.iter().enumerate() {
            assert_eq!(*v, i as u32 * mul + 1, "data[{i}]");
        }
        let counters: Vec<u32> = self.counters.read(ctx).unwrap();
        let n = self.count;
        assert_eq!(counters[0], n, "invocations");
        assert_eq!(counters[1], n * (n - 1) / 2, "index sum");
    }
}

#[test]
fn selftest_compute_pipeline() {
    let ctx = common::gpu();
    // Not a multiple of the workgroup size: exercises the bounds check.
    let t = SelfTest::new(&ctx, 1000);
    ctx.one_shot(|cmd| {
        t.record(&ctx, cmd, 3, 0);
        Ok(())
    })
    .unwrap();
    t.check(&ctx, 3);
    ctx.finish();
}

#[test]
fn timestamps_measure_named_scopes() {
    let ctx = common::gpu();
    let t = SelfTest::new(&ctx, 4096);
    let mut timer = GpuTimer::new(&ctx, 4).unwrap();
    ctx.one_shot(|cmd| {
        timer.reset(cmd);
        timer.begin(cmd, "subdivide")?;
        t.record(&ctx, cmd, 5, 1000);
        timer.end(cmd, "subdivide")?;
        timer.begin(cmd, "empty")?;
        timer.end(cmd, "empty")?;
        assert!(matches!(
            timer.end(cmd, "never begun"),
            Err(VkError::Usage(_))
        ));
        Ok(())
    })
    .unwrap();
    let times = timer.read().unwrap();
    let names: Vec<&str> = times.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["subdivide", "empty"]);
    for (name, ms) in &times {
        assert!(ms.is_finite() && *ms >= 0.0, "{name}: {ms} ms");
    }
    assert!(times[0].1 > 0.0, "a real dispatch takes time: {times:?}");
    println!("{times:?}");
    t.check(&ctx, 5);
    ctx.finish();
}

#[test]
fn fence_timeout_returns_an_error() {
    let ctx = common::gpu();
    let t = SelfTest::new(&ctx, 1024);
    // A pipeline's first run may also wait for its compile on a CPU device
    // (Context::take_compile_allowance), which lavapipe does inside the
    // submission, far beyond 1 ms: so the first, tiny dispatch still
    // finishes, and the timed one below is held to its timeout alone.
    let first = ctx.one_shot_with("first selftest dispatch", Duration::from_millis(1), |cmd| {
        t.record(&ctx, cmd, 1, 1);
        fill_buffer(&ctx, cmd, &t.counters, 0);
        Ok(())
    });
    if ctx.info().is_cpu {
        first.expect("a first run's compile does not count against the timeout");
    } else {
        ctx.wait_pending(Duration::from_secs(120)).unwrap();
    }
    // Each invocation spins a few million steps: far longer than 1 ms on any
    // device, yet bounded, so the work does finish and the test cannot hang.
    let start = std::time::Instant::now();
    let result = ctx.one_shot_with("long selftest dispatch", Duration::from_millis(1), |cmd| {
        t.record(&ctx, cmd, 2, 2_000_000);
        Ok(())
    });
    let returned = start.elapsed();
    match result {
        Err(VkError::FenceTimeout {
            label,
            timeout,
            allowance,
            waited,
            part,
        }) => {
            assert_eq!(label, "long selftest dispatch");
            assert_eq!(timeout, Duration::from_millis(1));
            assert_eq!(allowance, Duration::ZERO, "the pipeline ran before");
            assert!(waited >= timeout, "{waited:?}");
            assert_eq!(part, None, "one submission");
        }
        Err(e) => panic!("wrong error: {e}"),
        Ok(()) => panic!("a dispatch of seconds finished within 1 ms"),
    }
    assert_eq!(ctx.pending_count(), 1);
    // The buffers are still in use: wait before they are read or dropped.
    ctx.wait_pending(Duration::from_secs(120)).unwrap();
    println!(
        "timeout returned after {returned:?}; the dispatch took {:?}",
        start.elapsed()
    );
    assert_eq!(ctx.pending_count(), 0);
    t.check(&ctx, 2);
    ctx.finish();
}

#[test]
fn validation_errors_are_caught() {
    // A test that cannot fail is a defect: plant a real validation error.
    let ctx = common::gpu();
    let buf = Buffer::new(
        &ctx,
        "misaligned fill",
        64,
        STORAGE,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    ctx.one_shot(|cmd| {
        // dstOffset must be a multiple of 4 (VUID-vkCmdFillBuffer-dstOffset-00025).
        unsafe { ctx.device().cmd_fill_buffer(cmd, buf.handle(), 2, 4, 0) };
        Ok(())
    })
    .unwrap();
    assert!(ctx.validation_error_count() >= 1);
    let messages = ctx.validation_errors();
    assert!(
        messages.iter().any(|m| m.contains("dstOffset-00025")),
        "{messages:?}"
    );
    match ctx.check_validation() {
        Err(VkError::Validation { count, .. }) => assert!(count >= 1),
        other => panic!("expected a validation error, got {other:?}"),
    }

    // Synchronization validation: a copy reading a fill's output with no
    // barrier in between is a read-after-write hazard.
    let dst = Buffer::new(&ctx, "hazard copy", 64, STORAGE, MemoryLocation::GpuOnly).unwrap();
    ctx.one_shot(|cmd| {
        let d = ctx.device();
        let region = [vk::BufferCopy::default().size(64)];
        unsafe {
            d.cmd_fill_buffer(cmd, buf.handle(), 0, vk::WHOLE_SIZE, 1);
            d.cmd_copy_buffer(cmd, buf.handle(), dst.handle(), &region);
        }
        Ok(())
    })
    .unwrap();
    let messages = ctx.validation_errors();
    assert!(
        messages.iter().any(|m| m.contains("SYNC-HAZARD-READ")),
        "{messages:?}"
    );
    ctx.check_validation().unwrap_err();
    // Checking clears the count, so this test itself ends clean.
    ctx.finish();
}

#[test]
fn teardown_leaks_nothing() {
    // Hold the shared lock so this context's work does not overlap others.
    let shared = common::gpu();
    let ctx = Context::new(&common::test_options()).unwrap();
    let debug = ctx.debug_state();
    {
        let t = SelfTest::new(&ctx, 256);
        let mut timer = GpuTimer::new(&ctx, 1).unwrap();
        let image = Image::new(
            &ctx,
            &ImageDesc {
                name: "depth",
                width: 4,
                height: 4,
                format: vk::Format::D32_SFLOAT,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                samples: vk::SampleCountFlags::TYPE_1,
            },
        )
        .unwrap();
        ctx.one_shot(|cmd| {
            timer.reset(cmd);
            timer.begin(cmd, "selftest")?;
            t.record(&ctx, cmd, 1, 0);
            timer.end(cmd, "selftest")
        })
        .unwrap();
        t.check(&ctx, 1);
        timer.read().unwrap();
        assert!(ctx.live_allocations() > 0);
        drop(image);
    }
    assert_eq!(ctx.live_allocations(), 0, "every allocation was freed");
    drop(ctx);
    // Destroying the device reports every object still alive as an error.
    let (count, messages) = debug.take_errors();
    assert_eq!(count, 0, "{messages:#?}");
    shared.finish();
}

#[test]
fn spirv_checks_name_the_file_and_the_fix() {
    let label = Path::new("bad.spv");
    let err = bezier_subdiv::vk::spirv_words(label, &[1, 2, 3]).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("bad.spv") && msg.contains("multiple of 4"),
        "{msg}"
    );
    assert!(
        msg.contains("cargo run --release -p compile-shaders"),
        "{msg}"
    );
    let err = bezier_subdiv::vk::spirv_words(label, &[0u8; 20]).unwrap_err();
    assert!(err.to_string().contains("magic"), "{err}");
    let err = bezier_subdiv::vk::load_spirv("does-not-exist.comp").unwrap_err();
    assert!(err.to_string().contains("does-not-exist.comp.spv"), "{err}");
    let err = bezier_subdiv::vk::load_spirv_file(Path::new("/nonexistent/x.spv")).unwrap_err();
    assert!(err.to_string().contains("/nonexistent/x.spv"), "{err}");

    let good = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("spirv/selftest.comp.spv"))
        .unwrap();
    // The embedded copy is the file's.
    let embedded = bezier_subdiv::vk::load_spirv("selftest.comp").unwrap();
    assert_eq!(
        embedded,
        bezier_subdiv::vk::spirv_words(label, &good).unwrap()
    );
    let words = bezier_subdiv::vk::spirv_words(label, &good).unwrap();
    assert_eq!(words[0], 0x0723_0203);
    // Byte-swapped SPIR-V is valid too.
    let swapped: Vec<u8> = good
        .chunks(4)
        .flat_map(|w| [w[3], w[2], w[1], w[0]])
        .collect();
    assert_eq!(
        bezier_subdiv::vk::spirv_words(label, &swapped).unwrap(),
        words
    );
}
