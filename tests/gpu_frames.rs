//! Whole GPU frames (subdivision kernel + draw) on lavapipe with the
//! validation layer on: quads and vertex bits against the oracle over a grid
//! of ε and λ on both draw paths, the two paths' images, determinism (the
//! two methods' lists and images equal without a sort; the queue kernel's
//! sorted ones with a tiny queue), and hostile cameras. One device and one
//! set of pipelines per path for the whole binary.

mod common;

use bezier_subdiv::constants::*;
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::subdiv::Kernel;
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::patch::oracle::subdivide_parallel;
use bezier_subdiv::patch::quadnode::QuadNode;
use bezier_subdiv::patch::wedge::node_mesh;
use bezier_subdiv::renderer::Renderer;
use bezier_subdiv::scene::camera::Camera;
use bezier_subdiv::scene::geometry::SceneGeometry;
use common::scene;

const SIZE: (u32, u32) = (320, 180);

fn subdiv(gpu: &common::Gpu, geo: &SceneGeometry, path: DrawPath) -> Renderer {
    method(gpu, geo, "subdiv", path)
}

fn method(gpu: &common::Gpu, geo: &SceneGeometry, name: &str, path: DrawPath) -> Renderer {
    let mut r = common::renderer(gpu, geo, name, SIZE, MethodOptions::new(path));
    r.capture = true;
    r
}

fn view(cam: &Camera, eps: f64, lambda: f64, shade: u32) -> View {
    View::new(cam, SIZE, eps, lambda, shade)
}

/// Renders `v` and checks quads and vertex bits against the oracle;
/// returns the GPU ready list (in GPU order) and the image.
fn check_frame(
    r: &mut Renderer,
    geo: &SceneGeometry,
    v: &View,
    what: &str,
) -> (Vec<QuadNode>, Vec<u8>) {
    let (ready, _) = common::check_frame(r, v, what, &geo.patches, |params| {
        subdivide_parallel(&geo.patches, &geo.flags, params, 2)
    });
    let img = r.read_image().unwrap();
    (ready, img)
}

fn differing_pixels(a: &[u8], b: &[u8]) -> usize {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .filter(|(x, y)| x != y)
        .count()
}

/// Both subdivision methods against the oracle over ε × λ, the persistent
/// one on both draw paths; the paths' images agree, and the two methods
/// write the same list in the same order, so they draw the same image.
#[test]
fn grid_of_eps_and_lambda_on_both_paths() {
    let gpu = common::gpu();
    let (teapot, teapot_geo, teapot_shading) = common::scene_with_shading("teapot.toml");
    let (kitchen, kitchen_geo, kitchen_shading) = common::scene_with_shading("kitchen.toml");
    let mut mesh = subdiv(&gpu, &teapot_geo, DrawPath::Mesh);
    let mut fallback = subdiv(&gpu, &teapot_geo, DrawPath::Fallback);
    let mut indirect = method(&gpu, &teapot_geo, "subdiv-indirect", DrawPath::Mesh);
    let total = (SIZE.0 * SIZE.1) as usize;
    let mut worst = 0usize;
    let mut views = 0;
    for (s, geo, shading) in [
        (&teapot, &teapot_geo, &teapot_shading),
        (&kitchen, &kitchen_geo, &kitchen_shading),
    ] {
        mesh.set_geometry(geo, shading).unwrap();
        fallback.set_geometry(geo, shading).unwrap();
        indirect.set_geometry(geo, shading).unwrap();
        for frame in [0, s.frame_count() - 1] {
            let cam = s.frame_camera(frame).unwrap();
            for eps in [0.5, 1.0, 2.0] {
                for lambda in [0.0, 0.5, 1.0] {
                    let v = view(&cam, eps, lambda, SHADE_NORMAL);
                    let what = format!("{} frame {frame} eps {eps} lambda {lambda}", s.name);
                    let (ready_a, a) = check_frame(&mut mesh, geo, &v, &format!("{what} mesh"));
                    let (_, b) = check_frame(&mut fallback, geo, &v, &format!("{what} fallback"));
                    let (ready_c, c) =
                        check_frame(&mut indirect, geo, &v, &format!("{what} indirect"));
                    assert!(ready_a == ready_c, "{what}: the methods' lists differ");
                    assert_eq!(differing_pixels(&a, &c), 0, "{what}: indirect image");
                    views += 1;
                    let diff = differing_pixels(&a, &b);
                    worst = worst.max(diff);
                    assert!(
                        diff * 1000 <= total,
                        "{what}: paths differ in {diff} of {total} pixels"
                    );
                }
            }
        }
    }
    println!(
        "mesh vs fallback images: at most {worst} of {total} pixels differ; \
         per-depth = persistent list and image in all {views} views"
    );
    assert_eq!(views, 36);
    gpu.finish();
}

/// The same frame twice gives the same image, with either method and
/// between them (no sort: the level kernels' order is canonical); a node
/// memory small enough to take depths in parts gives the same ready set.
/// The queue kernel's order depends on timing, so it sorts: a queue of a
/// few dozen entries (stressed so that it overflows) gives the same ready
/// set and image as its default budget.
#[test]
fn determinism_and_tiny_queue() {
    let gpu = common::gpu();
    let (s, geo) = scene("kitchen.toml");
    let cam = s.frame_camera(0).unwrap();
    let v = view(&cam, 1.0, 0.5, SHADE_NORMAL);
    let mut r = subdiv(&gpu, &geo, DrawPath::Mesh);
    let (ready_a, img_a) = check_frame(&mut r, &geo, &v, "first");
    let (_, img_b) = check_frame(&mut r, &geo, &v, "second");
    assert_eq!(
        differing_pixels(&img_a, &img_b),
        0,
        "the same frame rendered twice differs"
    );
    let mut indirect = method(&gpu, &geo, "subdiv-indirect", DrawPath::Mesh);
    let (ready_i, img_i) = check_frame(&mut indirect, &geo, &v, "per-depth");
    assert!(ready_a == ready_i, "the two methods' lists differ");
    assert_eq!(
        differing_pixels(&img_a, &img_i),
        0,
        "the methods' images differ"
    );

    let mut small = MethodOptions::new(DrawPath::Mesh);
    small.per_method.levels.node_memory = 64 << 10;
    let mut parts = common::renderer(&gpu, &geo, "subdiv", SIZE, small);
    parts.capture = true;
    let (mut ready_p, img_p) = check_frame(&mut parts, &geo, &v, "small node memory");
    let report = parts.render(&v).unwrap();
    let split = report.stats.get_u64("rounds_split").unwrap();
    let diff = differing_pixels(&img_a, &img_p);
    println!("node memory of 64 KiB: {split} rounds in parts; image differs in {diff} pixels");
    assert!(split > 0);
    let (mut sa, mut sb) = (ready_a.clone(), std::mem::take(&mut ready_p));
    sa.sort();
    sb.sort();
    assert!(sa == sb);

    let queue = |capacity: u32| {
        let mut o = MethodOptions::new(DrawPath::Mesh);
        o.per_method.subdiv.kernel = Kernel::Queue;
        o.per_method.subdiv.queue_capacity = capacity;
        o
    };
    let mut big = common::renderer(&gpu, &geo, "subdiv", SIZE, queue(1 << 19));
    big.capture = true;
    let (mut ready_q, img_q) = check_frame(&mut big, &geo, &v, "queue kernel");
    let mut small = common::renderer(&gpu, &geo, "subdiv", SIZE, queue(32));
    small.capture = true;
    let mut stressed = v;
    stressed.params.flags |= FLAG_QUEUE_STRESS;
    let report = small.render(&stressed).unwrap();
    let spills = report.stats.get_u64("queue_spills").unwrap();
    let peak = report.stats.get_u64("queue_peak_items").unwrap();
    assert!(spills > 0, "{:?}", report.stats);
    assert!(peak <= 32);
    let (mut ready_t, img_t) = check_frame(&mut small, &geo, &stressed, "tiny queue");
    ready_q.sort();
    ready_t.sort();
    assert!(ready_q == ready_t);
    let diff = differing_pixels(&img_q, &img_t);
    println!(
        "tiny queue: {spills} spills, peak {peak}; image differs from the default budget in {diff} pixels"
    );
    assert_eq!(diff, 0);
    gpu.finish();
}

/// Degenerate patches, a camera inside the model and a camera with patches
/// behind it: no error, no NaN, the oracle's result.
#[test]
fn hostile_cameras() {
    let gpu = common::gpu();
    let (teapot, geo) = scene("teapot.toml");
    let mut r = subdiv(&gpu, &geo, DrawPath::Mesh);
    let base = teapot.camera;
    let cams = [
        // Under the teapot, looking at the collapsed bottom edge.
        Camera {
            position: [0.3, -0.2, -3.0],
            target: [0.0, 0.0, 0.0],
            ..base
        },
        // Onto the lid's apex, where another edge collapses.
        Camera {
            position: [0.1, 0.2, 6.0],
            target: [0.0, 0.0, 3.1],
            up: [0.0, 1.0, 0.0],
            ..base
        },
        // Inside the body.
        Camera {
            position: [0.0, 0.0, 1.2],
            target: [1.0, 0.3, 1.3],
            ..base
        },
        // In the spout's mouth, most patches behind or beside the camera.
        Camera {
            position: [3.2, 0.0, 2.3],
            target: [-2.0, 0.0, 1.0],
            near: 0.001,
            ..base
        },
    ];
    for (k, cam) in cams.iter().enumerate() {
        let v = view(cam, 1.0, 0.5, SHADE_NORMAL);
        let (ready, _) = check_frame(&mut r, &geo, &v, &format!("camera {k}"));
        let list = r.method().ready().unwrap().list();
        let capture: Vec<[f32; 4]> = list.capture.read(&gpu).unwrap();
        // Only the slots a node uses are written (corners, present pivots).
        for (i, q) in ready.iter().enumerate() {
            let mesh = node_mesh(*q, true);
            let pivots = mesh.tris[2..mesh.tri_count].iter().map(|t| t[2] as usize);
            for s in (0..4).chain(pivots) {
                let p = capture[NODE_MESH_SLOTS as usize * i + s];
                assert!(
                    p.iter().all(|x| x.is_finite()),
                    "camera {k}: node {i} slot {s}: {p:?}"
                );
            }
        }
        println!("camera {k}: {} ready quads", ready.len());
    }
    gpu.finish();
}
