//! The animation's update pass on lavapipe (validation layer on): it writes
//! exactly the CPU twin's model patches, shading patches and instance
//! records; every method draws the animated frame as it draws the same
//! scene uploaded static; `validate --time` holds (ready sets and positions
//! bit for bit) on both kernels and both draw paths, the hole test too; a
//! static scene records no update pass.

mod common;

use std::path::{Path, PathBuf};

use bezier_subdiv::anim::AnimatedScene;
use bezier_subdiv::commands::validate::{run, ValidateArgs};
use bezier_subdiv::commands::{AnimTime, GpuRequest};
use bezier_subdiv::draw::{DrawPath, DrawRequest};
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::levels;
use bezier_subdiv::methods::subdiv::Kernel;
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::renderer::{Renderer, RendererOptions};
use bezier_subdiv::scene::desc::Scene;

const SIZE: (u32, u32) = (320, 180);

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
}

fn demo() -> (Scene, AnimatedScene) {
    let scene = Scene::load(&scene_path("anim.toml")).unwrap();
    let loaded = scene.load_animated().unwrap();
    (scene, loaded)
}

fn options(draw: DrawPath) -> RendererOptions {
    RendererOptions {
        size: SIZE,
        background: [0.1, 0.1, 0.1, 1.0],
        frames_in_flight: 2,
        methods: {
            let mut o = MethodOptions::new(draw);
            o.per_method.ground_truth.grid = 8;
            o
        },
    }
}

/// `subdiv` on the mesh path over `loaded`, its animation set.
fn animated_subdiv(gpu: &common::Gpu, loaded: &AnimatedScene) -> Renderer {
    let mut r = Renderer::new(
        gpu.arc(),
        &loaded.geometry,
        &loaded.shading,
        "subdiv",
        options(DrawPath::Mesh),
    )
    .unwrap();
    r.set_animation(loaded.animation.clone()).unwrap();
    r
}

fn view(scene: &Scene) -> View {
    View::new(
        &scene.camera,
        SIZE,
        scene.view.eps,
        scene.view.lambda,
        bezier_subdiv::constants::SHADE_NORMAL,
    )
}

/// After an animated frame, set 0 holds bit for bit what the CPU twin
/// (`Animation::pose`) makes: the moving models' model patches and shading
/// patches, and every instance record; at several times, the 180° twist
/// among them.
#[test]
fn the_update_pass_writes_what_the_cpu_twin_makes() {
    let gpu = common::gpu();
    let (scene, loaded) = demo();
    let mut r = animated_subdiv(&gpu, &loaded);
    let v = view(&scene);
    for t in [0.0, 0.6, 2.0, 3.7] {
        r.set_time(t);
        let report = r.render(&v).unwrap();
        assert!(report.ms("update").is_some(), "no update scope");
        let (geo, shading) = loaded.at(t);
        let ctx = r.context().clone();
        let s = r.scene();
        let patches: Vec<u32> = s.patches.read(&ctx).unwrap();
        let want: Vec<u32> = geo
            .instances
            .patches
            .iter()
            .flat_map(|p| p.pts.iter().flat_map(|q| q.to_array().map(f32::to_bits)))
            .collect();
        assert_eq!(patches, want, "model patches at t = {t}");
        let vectors: Vec<u32> = s.shading.read(&ctx).unwrap();
        let want: Vec<u32> = shading
            .model
            .iter()
            .flat_map(|p| p.to_floats().map(f32::to_bits))
            .collect();
        assert_eq!(vectors, want, "shading patches at t = {t}");
        let records: Vec<u32> = s.instances.read(&ctx).unwrap();
        let want: Vec<u32> = bytemuck::cast_slice(geo.instances.records()).to_vec();
        assert_eq!(
            records[..want.len()],
            want[..],
            "instance records at t = {t}"
        );
    }
    gpu.finish();
}

/// Every method draws the animated frame exactly as it draws the scene at
/// that time uploaded static (the same patch bits, no change to any
/// method's code).
#[test]
fn every_method_draws_the_animated_frame() {
    let gpu = common::gpu();
    let (scene, loaded) = demo();
    let t = 2.0;
    let (geo, shading) = loaded.at(t);
    let v = view(&scene);
    for method in [
        "subdiv",
        "subdiv-indirect",
        "tess",
        "tess-reparam",
        "cudatess",
        "ground-truth",
    ] {
        let mut moving = Renderer::new(
            gpu.arc(),
            &loaded.geometry,
            &loaded.shading,
            method,
            options(DrawPath::Mesh),
        )
        .unwrap();
        moving.set_animation(loaded.animation.clone()).unwrap();
        moving.set_time(t);
        let report = moving.render(&v).unwrap();
        assert!(report.ms("update").is_some(), "{method}: no update scope");
        let animated = moving.read_image().unwrap();
        let mut still =
            Renderer::new(gpu.arc(), &geo, &shading, method, options(DrawPath::Mesh)).unwrap();
        let report = still.render(&v).unwrap();
        assert!(
            report.ms("update").is_none(),
            "{method}: a static scene updated"
        );
        let image = still.read_image().unwrap();
        let differ = animated
            .chunks_exact(4)
            .zip(image.chunks_exact(4))
            .filter(|(a, b)| a != b)
            .count();
        println!("{method}: {differ} pixels differ");
        assert_eq!(differ, 0, "{method}");
        // And the frame moved: the scene at rest looks different.
        moving.set_time(0.0);
        moving.render(&v).unwrap();
        assert_ne!(moving.read_image().unwrap(), animated, "{method}");
    }
    gpu.finish();
}

fn validate_args(draw: DrawRequest, method: &str, time: f64, holes: bool) -> ValidateArgs {
    let mut g = GpuRequest::new(scene_path("anim.toml"));
    g.size = SIZE;
    g.draw = draw;
    g.method = method.into();
    g.validation = true;
    g.time = Some(AnimTime::Seconds(time));
    ValidateArgs {
        gpu: g,
        frames: Vec::new(),
        skip_holes: !holes,
        debug_dir: Some(common::output_dir("anim-holes")),
    }
}

/// `validate --time`: ready sets and positions bit for bit on the animated
/// frames, both subdivision kernels and both draw paths, at the 180° twist
/// and in between.
#[test]
fn animated_frames_validate_on_both_kernels_and_paths() {
    let _gpu = common::gpu();
    for (method, draw, time) in [
        ("subdiv", DrawRequest::Mesh, 2.0),
        ("subdiv", DrawRequest::Fallback, 2.0),
        ("subdiv-indirect", DrawRequest::Mesh, 0.9),
        ("subdiv-indirect", DrawRequest::Fallback, 2.0),
    ] {
        let report = run(&validate_args(draw, method, time, false)).unwrap();
        println!("{}", report.table);
        assert!(report.ok(), "{}", report.table);
        assert!(report.table.contains(&format!("time {time} s")));
    }
    // The work-queue kernel too.
    let mut a = validate_args(DrawRequest::Mesh, "subdiv", 2.0, false);
    a.gpu.per_method.subdiv.kernel = Kernel::Queue;
    let report = run(&a).unwrap();
    assert!(report.ok(), "{}", report.table);
}

/// The hole test on an animated frame (the 180° twist): no hole, and with
/// wedges off the cracks are still found.
#[test]
fn animated_frames_have_no_holes() {
    let _gpu = common::gpu();
    let report = run(&validate_args(DrawRequest::Mesh, "subdiv", 2.0, true)).unwrap();
    println!("{}", report.table);
    assert!(report.ok(), "{}", report.table);
    let torus = report
        .results
        .iter()
        .find(|r| r.check == "holes catmark_torus.obj")
        .expect("the torus is hole-tested");
    assert!(torus.detail.contains("wedges off"), "{}", torus.detail);
}

/// `--time` on a scene that does not move is refused with a sentence.
#[test]
fn time_on_a_static_scene_is_refused() {
    let mut a = validate_args(DrawRequest::Mesh, "subdiv", 1.0, false);
    a.gpu.scene = scene_path("teapot.toml");
    let e = run(&a).unwrap_err().to_string();
    assert!(e.contains("does not move"), "{e}");
}

/// Instance culling by box follows the animation: a cube waved 6 units up
/// out of its box at rest, and a keyed cube moved there, with the camera
/// seeing only where they went (their boxes at rest lie below the
/// frustum). A box kept from load would cull both whole: the oracle's
/// roots (`levels::root_patches`) would be empty and the GPU would draw
/// nothing.
#[test]
fn moved_instances_are_not_culled_by_their_box_at_rest() {
    let gpu = common::gpu();
    let dir = common::output_dir("anim-moved-box");
    let cube = scene_path("models/catmark_cube.obj");
    let toml = format!(
        "[animation]\nduration = 4.0\n\
         [camera]\nposition = [0.0, -30.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\n\
         [[model]]\nname = \"waved\"\nfile = {cube:?}\n\
         [[model.deform]]\nkind = \"wave\"\naxis = \"z\"\nalong = \"x\"\n\
         amplitude = 6.0\nwavelength = 1000.0\nspeed = 0.75\n\
         [[model]]\nname = \"keyed\"\nfile = {cube:?}\n[[model.instance]]\n\
         [[model.instance.key]]\ntime = 0.0\n\
         [[model.instance.key]]\ntime = 1.0\ntranslate = [4.0, 0.0, 6.0]\n"
    );
    let path = dir.join("moved.toml");
    std::fs::write(&path, toml).unwrap();
    let mut scene = Scene::load(&path).unwrap();
    let loaded = scene.load_animated().unwrap();
    let t = 1.0;
    let (geo, _) = loaded.at(t);
    // Both moved clear of where they were at load.
    let pts = |g: &bezier_subdiv::scene::geometry::SceneGeometry| {
        let mut lo = glam::Vec3::splat(f32::MAX);
        let mut hi = glam::Vec3::splat(-f32::MAX);
        for q in g.patches.iter().flat_map(|p| p.pts) {
            lo = lo.min(q);
            hi = hi.max(q);
        }
        (lo, hi)
    };
    let (rest_lo, rest_hi) = pts(&loaded.geometry);
    let (lo, hi) = pts(&geo);
    assert!(
        rest_hi.z < 1.5 && lo.z > 4.0,
        "rest {rest_lo}..{rest_hi}, at {t}: {lo}..{hi}"
    );
    // Look at the moved cubes from the front, the bottom plane above both
    // boxes at rest.
    let c = (lo + hi) * 0.5;
    scene.camera.position = [f64::from(c.x), -12.0, f64::from(c.z)];
    scene.camera.target = [f64::from(c.x), 0.0, f64::from(c.z)];
    scene.camera.fov_y_deg = 30.0;
    let v = view(&scene);
    let mut r = animated_subdiv(&gpu, &loaded);
    let vp = r.effective_params(&v);
    assert_ne!(vp.flags & bezier_subdiv::constants::FLAG_FRUSTUM_CULL, 0);
    // With the boxes of the cubes at rest, as a static scene has them,
    // both would be culled whole.
    let mut stale = loaded.geometry.instances.instances.clone();
    for b in &mut stale {
        *b = b.bounded(&loaded.geometry.patches[b.ids()]);
    }
    assert!(
        levels::root_patches(&stale, &vp).is_empty(),
        "the camera sees the cubes at rest"
    );
    // At t the GPU draws them.
    r.set_time(t);
    r.render(&v).unwrap();
    let image = r.read_image().unwrap();
    let background = image[..4].to_vec();
    let drawn = image
        .chunks_exact(4)
        .filter(|p| *p != &background[..])
        .count();
    println!("{drawn} pixels drawn at t = {t}");
    assert!(
        drawn > 1000,
        "{drawn} pixels drawn: the moved cubes were culled"
    );
    // And the oracle's roots hold every patch of both cubes.
    let roots = levels::root_patches(&geo.instances.instances, &vp);
    assert_eq!(
        roots.len(),
        geo.patches.len(),
        "the oracle culled a moved instance"
    );
    gpu.finish();
}

/// A keyed instance's record carries its model's box placed by the frame's
/// transform, so an instance that moved out of view is culled whole, as a
/// static one is (keyed records were once all unbounded, culled only patch
/// by patch). The box holds every placed control point at every time,
/// under rotation and non-uniform scale; the oracle's roots follow it.
#[test]
fn keyed_instances_that_moved_out_of_view_are_culled_whole() {
    let gpu = common::gpu();
    let dir = common::output_dir("anim-keyed-box");
    let cube = scene_path("models/catmark_cube.obj");
    let toml = format!(
        "[animation]\nduration = 2.0\n\
         [camera]\nposition = [0.0, -30.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 30.0\n\
         [[model]]\nname = \"stays\"\nfile = {cube:?}\n[[model.instance]]\n\
         [[model.instance.key]]\ntime = 0.0\n\
         [[model.instance.key]]\ntime = 1.0\nrotate_deg = [0.0, 0.0, 90.0]\n\
         [[model]]\nname = \"leaves\"\nfile = {cube:?}\n[[model.instance]]\n\
         [[model.instance.key]]\ntime = 0.0\ntranslate = [2.0, 0.0, 0.0]\n\
         [[model.instance.key]]\ntime = 1.0\ntranslate = [60.0, 0.0, 3.0]\n\
         rotate_deg = [30.0, 45.0, 170.0]\nscale = [3.0, 0.5, 1.5]\n"
    );
    let path = dir.join("keyed.toml");
    std::fs::write(&path, toml).unwrap();
    let scene = Scene::load(&path).unwrap();
    let loaded = scene.load_animated().unwrap();
    for t in [0.0, 0.3, 0.5, 0.8, 1.0] {
        let (geo, _) = loaded.at(t);
        let table = &geo.instances;
        for (i, record) in table.instances.iter().enumerate() {
            let (lo, hi) = record.bounds();
            assert!(hi.x - lo.x < 1e6, "instance {i} at {t} is unbounded");
            let model = &table.patches[record.source as usize..][..record.count as usize];
            for p in model.iter().flat_map(|p| p.pts) {
                let q = record.point(p);
                assert!(
                    q.cmpge(lo).all() && q.cmple(hi).all(),
                    "instance {i} at {t}: {q} outside {lo}..{hi}"
                );
            }
        }
    }
    let v = view(&scene);
    let mut r = animated_subdiv(&gpu, &loaded);
    let vp = r.effective_params(&v);
    for (t, culled) in [(0.0, 0), (1.0, 1)] {
        r.set_time(t);
        let report = r.render(&v).unwrap();
        let (geo, _) = loaded.at(t);
        let roots = levels::root_patches(&geo.instances.instances, &vp);
        let per_cube = geo.patches.len() / 2;
        assert_eq!(
            roots.len(),
            per_cube * (2 - culled as usize),
            "oracle roots at {t}"
        );
        assert_eq!(
            report.stats.get_u64("instances_culled"),
            Some(culled),
            "at {t}"
        );
    }
    gpu.finish();
}
