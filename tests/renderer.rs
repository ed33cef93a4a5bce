//! The renderer as a long-lived object (lavapipe, validation on): frames in
//! flight keep their own figures, switching methods and views reuses the
//! uploaded scene and the loaded shaders, a failed scene replacement
//! leaves the old state usable, and work that outlives its fence wait keeps
//! everything it uses alive.

mod common;

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use std::time::{Duration, Instant};

use bezier_subdiv::constants::{NODE_MESH_TRIS, SHADE_NORMAL};
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::ground_truth::constants::G_MAX_PARTS;
use bezier_subdiv::methods::ground_truth::{plan_parts, PART_TRIANGLES};
use bezier_subdiv::methods::{MethodOptions, RenderError};
use bezier_subdiv::patch::oracle::subdivide;
use bezier_subdiv::renderer::{Renderer, RendererOptions};
use bezier_subdiv::scene::geometry::{SceneGeometry, SceneShading};
use bezier_subdiv::vk::{Context, ContextOptions, VkError};

const SIZE: (u32, u32) = (256, 144);

fn views() -> (SceneGeometry, Vec<View>) {
    let (s, geo) = common::scene("teapot.toml");
    let views = (0..s.frame_count())
        .map(|k| View::new(&s.frame_camera(k).unwrap(), SIZE, 1.0, 0.5, SHADE_NORMAL))
        .collect();
    (geo, views)
}

fn subdiv(gpu: &common::Gpu, geo: &SceneGeometry) -> Renderer {
    common::renderer(gpu, geo, "subdiv", SIZE, MethodOptions::new(DrawPath::Mesh))
}

fn oracle_quads(geo: &SceneGeometry, v: &View) -> u64 {
    subdivide(&geo.patches, &geo.flags, &v.params).ready.len() as u64
}

/// Two frames in flight at once each report their own view's figures; a
/// frame whose slot was reused before it was collected is refused.
#[test]
fn frames_in_flight_keep_their_own_figures() {
    let gpu = common::gpu();
    let (geo, views) = views();
    let mut r = subdiv(&gpu, &geo);
    let (a, b) = (&views[0], &views[1]);
    let ta = r.submit(a).unwrap();
    let tb = r.submit(b).unwrap();
    let (ra, _) = r.collect(ta).unwrap();
    let (rb, _) = r.collect(tb).unwrap();
    let (qa, qb) = (oracle_quads(&geo, a), oracle_quads(&geo, b));
    assert_ne!(
        qa, qb,
        "the two views must differ for this test to mean anything"
    );
    assert_eq!(ra.stats.get_u64("ready_quads"), Some(qa));
    assert_eq!(rb.stats.get_u64("ready_quads"), Some(qb));
    assert!(ra.ms("subdivide").is_some() && rb.ms("draw").is_some());

    // Three submissions into two slots: the first is overwritten.
    let t1 = r.submit(a).unwrap();
    let t2 = r.submit(b).unwrap();
    let t3 = r.submit(a).unwrap();
    let err = r.collect(t1).err().unwrap();
    assert!(err.to_string().contains("reused"), "{err}");
    assert_eq!(
        r.collect(t2).unwrap().0.stats.get_u64("ready_quads"),
        Some(qb)
    );
    assert_eq!(
        r.collect(t3).unwrap().0.stats.get_u64("ready_quads"),
        Some(qa)
    );
    let err = r.collect(t3).err().unwrap();
    assert!(err.to_string().contains("already collected"), "{err}");
    gpu.finish();
}

/// A `subdiv` renderer on the mesh path with the ground truth's grid at
/// 8, and those options (for changing one knob).
fn grid8_subdiv(gpu: &common::Gpu, geo: &SceneGeometry) -> (Renderer, MethodOptions) {
    let mut options = MethodOptions::new(DrawPath::Mesh);
    options.per_method.ground_truth.grid = 8;
    let r = common::renderer(gpu, geo, "subdiv", SIZE, options.clone());
    (r, options)
}

/// Switching methods, ε and λ keeps the uploaded scene, the shader modules
/// and the methods already made.
#[test]
fn switching_reuses_scene_shaders_and_methods() {
    let gpu = common::gpu();
    let (geo, views) = views();
    let (mut r, options) = grid8_subdiv(&gpu, &geo);
    let patches = r.scene().patches.handle();
    r.render(&views[0]).unwrap();
    r.set_method("ground-truth").unwrap();
    let gt = r.render(&views[0]).unwrap();
    assert_eq!(gt.method, "ground-truth");
    assert_eq!(
        gt.stats.triangles,
        32 * 2 * 64,
        "32 teapot patches of 8x8 cells"
    );
    let loaded = r.shaders_loaded();
    let (s, _) = common::scene("teapot.toml");
    for (k, eps) in [0.5, 1.0, 2.0, 4.0].into_iter().enumerate() {
        let v = View::new(&s.camera, SIZE, eps, 0.25 * k as f64, SHADE_NORMAL);
        r.set_method(if k % 2 == 0 { "subdiv" } else { "ground-truth" })
            .unwrap();
        r.render(&v).unwrap();
    }
    // A changed grid is applied in place.
    let mut grid4 = options;
    grid4.per_method.ground_truth.grid = 4;
    r.set_options(grid4.clone()).unwrap();
    r.set_method("ground-truth").unwrap();
    assert_eq!(r.render(&views[0]).unwrap().stats.triangles, 32 * 2 * 16);
    assert_eq!(r.shaders_loaded(), loaded, "shaders were loaded again");
    assert_eq!(r.methods_made(), 2);
    assert_eq!(
        r.scene().patches.handle(),
        patches,
        "the scene was uploaded again"
    );

    // A frame in flight when the methods are remade is refused, never
    // finished by whichever method took its place in the list.
    r.set_method("subdiv").unwrap();
    let t = r.submit(&views[0]).unwrap();
    r.set_options(MethodOptions {
        draw: DrawPath::Fallback,
        ..grid4
    })
    .unwrap();
    let err = r.collect(t).err().unwrap();
    assert!(err.to_string().contains("remade"), "{err}");
    assert_eq!(r.method().draw_path(), "fallback");
    gpu.finish();
}

/// Every frame's triangles come from one primitive query, so the count
/// means the same for every method: on the mesh path it equals the
/// subdivision's own count (wedges included, missing wedges culled); on the
/// fallback path the query also counts the degenerate triangle standing in
/// for each missing wedge (6 slots per ready node), which the frame's count
/// leaves out, so both paths report the same triangles for the same view
/// (the fallback once reported 2.8 times the mesh path's on the herd);
/// for the ground truth it is 2·grid² per visible patch.
#[test]
fn the_triangle_query_counts_what_each_method_draws() {
    use bezier_subdiv::vk::PrimitiveQuery;
    let gpu = common::gpu();
    let (geo, views) = views();
    let (mut r, options) = grid8_subdiv(&gpu, &geo);
    let mut mesh_counts = Vec::new();
    for v in &views[..2] {
        let mesh = r.render(v).unwrap();
        mesh_counts.push(mesh.triangles());
        assert_eq!(
            mesh.primitives.map(|(q, _)| q),
            Some(PrimitiveQuery::MeshGenerated)
        );
        assert!(mesh.stats.triangles > 0);
        assert_eq!(mesh.triangles(), mesh.stats.triangles, "mesh path");
        assert!(
            mesh.stats.get_u64("wedge_triangles").unwrap() > 0,
            "the view must have wedges for the comparison to mean anything"
        );
    }
    r.set_method("ground-truth").unwrap();
    let gt = r.render(&views[0]).unwrap();
    assert_eq!(
        gt.primitives.map(|(q, _)| q),
        Some(PrimitiveQuery::Generated)
    );
    let visible = gt.stats.get_u64("visible_patches").unwrap();
    assert_eq!(gt.triangles(), visible * 2 * 64);
    r.set_options(MethodOptions {
        draw: DrawPath::Fallback,
        ..options
    })
    .unwrap();
    r.set_method("subdiv").unwrap();
    let fallback = r.render(&views[0]).unwrap();
    let quads = fallback.stats.get_u64("ready_quads").unwrap();
    // The fallback draws every node's NODE_MESH_TRIS slots (missing wedges
    // as degenerate triangles the query still counts).
    let slots = u64::from(NODE_MESH_TRIS);
    let (_, primitives) = fallback.primitives.expect("a primitive query");
    assert_eq!(primitives, slots * quads, "fallback path's query");
    assert!(fallback.stats.triangles < slots * quads);
    assert_eq!(
        fallback.stats.placeholder_triangles,
        slots * quads - fallback.stats.triangles
    );
    assert_eq!(
        fallback.triangles(),
        fallback.stats.triangles,
        "fallback path"
    );
    assert_eq!(
        fallback.triangles(),
        mesh_counts[0],
        "the paths on one view"
    );
    gpu.finish();
}

/// A scene that cannot be uploaded (flags or shading patches that do not
/// match the patches) is refused and the renderer keeps drawing the old
/// one, identically.
#[test]
fn failed_scene_replacement_leaves_the_old_one() {
    let gpu = common::gpu();
    let (geo, views) = views();
    let mut r = subdiv(&gpu, &geo);
    r.render(&views[0]).unwrap();
    let before = r.read_image().unwrap();
    let bad = SceneGeometry {
        patches: geo.patches.clone(),
        flags: vec![0; 3],
        models: Vec::new(),
        weights: Vec::new(),
        ..Default::default()
    };
    let shading = SceneShading::from_geometry(&geo.patches);
    let err = r.set_geometry(&bad, &shading).err().unwrap();
    assert!(err.to_string().contains("flag words"), "{err}");
    let short = SceneShading::from_geometry(&geo.patches[1..]);
    let err = r.set_geometry(&geo, &short).err().unwrap();
    assert!(err.to_string().contains("shading patches"), "{err}");
    let report = r.render(&views[0]).unwrap();
    assert_eq!(
        report.stats.get_u64("ready_quads"),
        Some(oracle_quads(&geo, &views[0]))
    );
    assert_eq!(r.read_image().unwrap(), before);
    gpu.finish();
}

/// The queue kernel (whose planted phantom item keeps it running until its
/// iteration cap), with no barriers that a loaded CPU could stretch.
fn queue_options() -> MethodOptions {
    let mut o = MethodOptions::new(DrawPath::Mesh);
    o.per_method.subdiv.kernel = bezier_subdiv::methods::subdiv::Kernel::Queue;
    o
}

fn short_timeout_renderer(ctx: &Arc<Context>, geo: &SceneGeometry) -> Renderer {
    let mut methods = queue_options();
    methods.per_method.subdiv.plant_endless_loop = true;
    Renderer::new(
        Arc::clone(ctx),
        geo,
        &SceneShading::from_geometry(&geo.patches),
        "subdiv",
        RendererOptions {
            size: SIZE,
            background: [0.0; 4],
            frames_in_flight: 2,
            methods,
        },
    )
    .unwrap()
}

/// A frame that outlives its fence wait: the wait fails with a timeout, the
/// frame's buffers stay alive, the renderer recovers once the GPU is done
/// (here the planted endless loop ends at the kernel's iteration cap), and
/// it then renders and tears down cleanly. Dropping a renderer whose frame
/// is still running leaks instead of freeing memory under the GPU.
#[test]
fn fence_timeout_keeps_resources_alive() {
    // Its own context (a 50 ms fence timeout); the shared lock keeps other
    // GPU tests off the device meanwhile.
    let shared = common::gpu();
    let ctx = Arc::new(
        Context::new(&ContextOptions {
            fence_timeout: Duration::from_millis(50),
            // The first frame's compile would otherwise be allowed minutes.
            compile_allowance: Duration::ZERO,
            ..common::test_options()
        })
        .unwrap(),
    );
    let debug = ctx.debug_state();
    let (geo, views) = views();
    let mut r = short_timeout_renderer(&ctx, &geo);
    let allocated = ctx.live_allocations();
    let ticket = r.submit(&views[0]).unwrap();
    match r.collect(ticket) {
        Err(RenderError::Vk(VkError::FenceTimeout { .. })) => {}
        other => panic!(
            "expected a fence timeout, got {:?}",
            other.map(|(r, _)| r.method)
        ),
    }
    assert_eq!(ctx.live_allocations(), allocated, "something was freed");
    let start = Instant::now();
    while r.wait_idle().is_err() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the planted loop never ended"
        );
    }
    println!(
        "the frame ended {:?} after its wait timed out",
        start.elapsed()
    );
    r.set_options(queue_options()).unwrap();
    let report = r.render(&views[0]).unwrap();
    assert_eq!(
        report.stats.get_u64("ready_quads"),
        Some(oracle_quads(&geo, &views[0]))
    );
    drop(r);
    assert_eq!(ctx.live_allocations(), 0, "the renderer freed everything");
    assert!(!ctx.is_hung());

    // Dropped while its frame still runs: declared hung, nothing freed.
    let mut r = short_timeout_renderer(&ctx, &geo);
    let allocated = ctx.live_allocations();
    let _ = r.submit(&views[0]).unwrap();
    drop(r);
    assert!(
        ctx.is_hung(),
        "a renderer dropped mid-frame must declare the device hung"
    );
    assert_eq!(
        ctx.live_allocations(),
        allocated,
        "memory was freed under the GPU"
    );
    drop(ctx);
    let (count, messages) = debug.take_errors();
    assert_eq!(count, 0, "{messages:#?}");
    shared.finish();
}

/// The ground truth of a large scene is submitted in parts of bounded size,
/// each its own fence wait, reported to the progress sink as it finishes;
/// the parts draw exactly the image and the counts of one submission, with
/// and without multisampling (the later parts load colour samples and
/// depth).
#[test]
fn ground_truth_in_parts_draws_what_one_submission_draws() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("kitchen.toml");
    let view = View::new(&s.frame_camera(0).unwrap(), SIZE, 1.0, 0.5, SHADE_NORMAL);
    for samples in [1, 4] {
        let draw = |part_triangles: u64| {
            let mut options = MethodOptions::new(DrawPath::Mesh);
            options.per_method.ground_truth.grid = 8;
            options.samples = samples;
            options.per_method.ground_truth.part_triangles = part_triangles;
            let mut r = common::renderer(&gpu, &geo, "ground-truth", SIZE, options);
            let seen = Rc::new(RefCell::new(Vec::new()));
            let sink = Rc::clone(&seen);
            r.set_progress(Some(Box::new(move |p| {
                sink.borrow_mut().push((p.done, p.total))
            })));
            let report = r.render(&view).unwrap();
            let image = r.read_image().unwrap();
            let seen = seen.borrow().clone();
            (image, report, seen)
        };
        let (whole, one, seen_one) = draw(u64::MAX);
        // 128 triangles per patch at grid 8: 1,000 patches per part.
        let (split, many, seen_many) = draw(128 * 1000);
        let parts = |r: &bezier_subdiv::renderer::FrameReport| r.stats.get_u64("parts");
        assert_eq!(parts(&one), Some(1));
        assert!(
            seen_one.is_empty(),
            "one part reports nothing: {seen_one:?}"
        );
        let n = geo.patches.len().div_ceil(1000) as u32;
        assert_eq!(parts(&many), Some(u64::from(n)), "{samples}x");
        let expected: Vec<(u32, u32)> = (0..=n).map(|k| (k, n)).collect();
        assert_eq!(seen_many, expected);
        assert_eq!(one.triangles(), many.triangles());
        assert_eq!(
            one.stats.get_u64("visible_patches"),
            many.stats.get_u64("visible_patches")
        );
        assert_eq!(one.stats.culled_patches, many.stats.culled_patches);
        assert!(one.triangles() > 0);
        let differing = whole.iter().zip(&split).filter(|(a, b)| a != b).count();
        assert_eq!(differing, 0, "{samples}x: the parts drew another image");
    }
    // The README's `render --method tess --flip` once ran out of its wait
    // on a busy 2-core lavapipe: the kitchen's ground truth at grid 64 was
    // one submission of 2.6e8 triangles. Its parts now hold at most
    // PART_TRIANGLES each (about 2 s there), and cover every patch.
    let patches = geo.patches.len() as u32;
    assert!(geo.pn.triangles.is_empty());
    let plan = plan_parts(patches, 0, 64, PART_TRIANGLES, G_MAX_PARTS);
    assert!(plan.parts() > 1, "{plan:?}");
    assert!(u64::from(plan.patches_per_part) * 2 * 64 * 64 <= PART_TRIANGLES);
    assert!(
        plan.patches_per_part * plan.patch_parts >= patches,
        "{plan:?}"
    );
    gpu.finish();
}
