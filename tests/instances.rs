//! Instancing on lavapipe (validation layer on): each model's patches are
//! uploaded once and every shader places them by their instance's
//! transform; the GPU's ready sets and positions still equal the oracle's
//! bit for bit (the oracle reads the host's world patches, made by the
//! transform's f32 twin), and the shared-edge checks of the tessellators
//! and the hole test hold, for identity, rotated, scaled and mirrored
//! instances of cages, `.bpt` and rational models.

mod common;

use std::path::{Path, PathBuf};

use bezier_subdiv::commands::validate::{run, ValidateArgs};
use bezier_subdiv::commands::GpuRequest;
use bezier_subdiv::draw::DrawRequest;
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::scene::desc::Scene;
use bezier_subdiv::scene::instances::{cluster_set_words, GPU_BYTES_PER_INSTANCE, INSTANCE_BYTES};

/// Instances of every kind of transform: the identity, rotated and scaled,
/// mirrored (one axis negative, then two), and a lattice.
const INSTANCES: &str = r#"
[[model.instance]]
[[model.instance]]
translate = [3.0, 0.5, -0.5]
rotate_deg = [10.0, 20.0, 30.0]
scale = [1.5, 0.75, 1.25]
[[model.instance]]
translate = [-3.0, 0.0, 0.25]
rotate_deg = [-35.0, 5.0, 60.0]
scale = [1.0, -2.0, 1.0]
[[model.instance]]
translate = [0.0, -3.5, 0.0]
scale = [-1.0, -1.0, 1.0]
[[model.instance]]
translate = [0.0, 3.5, 0.0]
scale = 0.5
grid = { count = [2, 1, 1], step = [1.5, 0.0, 0.0] }
"#;

/// A scene of `models` (files of scenes/models), each with [`INSTANCES`],
/// written under the test's output directory.
fn scene(tag: &str, models: &[&str]) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/models");
    let mut text = String::from(
        r#"name = "instances"
[camera]
position = [9.0, -11.0, 7.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov_y_deg = 45.0
near = 0.05
far = 200.0

[camera_path]
frames = 2
[[camera_path.key]]
position = [-8.0, 6.0, -4.0]
target = [0.0, 0.0, 0.5]
"#,
    );
    for file in models {
        text.push_str(&format!(
            "\n[[model]]\nfile = {:?}\n{INSTANCES}",
            root.join(file).to_str().unwrap()
        ));
    }
    let dir = common::output_dir(tag);
    let path = dir.join("instances.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn args(scene: &Path, method: &str, draw: DrawRequest) -> ValidateArgs {
    let mut gpu = GpuRequest::new(scene.to_path_buf());
    gpu.size = (320, 180);
    gpu.draw = draw;
    gpu.method = method.into();
    gpu.validation = true;
    gpu.per_method.ground_truth.grid = 16;
    ValidateArgs {
        gpu,
        frames: Vec::new(),
        skip_holes: false,
        debug_dir: Some(common::output_dir("instances-holes")),
    }
}

/// The polynomial models under every method that draws them: subdivision
/// (both kernels, both draw paths) against the oracle, the tessellators'
/// shared edges, and the hole test.
#[test]
fn placed_instances_validate_on_every_method() {
    let _gpu = common::gpu();
    let path = scene("instances-poly", &["catmark_cube.obj", "teapot.bpt"]);
    for (method, draw) in [
        ("subdiv", DrawRequest::Mesh),
        ("subdiv-indirect", DrawRequest::Fallback),
        ("tess", DrawRequest::Auto),
        ("tess-reparam", DrawRequest::Auto),
        ("cudatess", DrawRequest::Auto),
    ] {
        let report = run(&args(&path, method, draw)).unwrap();
        println!("{}", report.table);
        assert!(report.ok(), "{method}: {}", report.table);
    }
}

/// Rational models (weights reordered with the points where an instance
/// mirrors) under the methods that draw them.
#[test]
fn placed_rational_instances_validate() {
    let _gpu = common::gpu();
    let path = scene("instances-rational", &["rational_torus.rbpt"]);
    for (method, draw) in [
        ("subdiv", DrawRequest::Fallback),
        ("subdiv-indirect", DrawRequest::Mesh),
        ("cudatess", DrawRequest::Auto),
    ] {
        let report = run(&args(&path, method, draw)).unwrap();
        println!("{}", report.table);
        assert!(report.ok(), "{method}: {}", report.table);
    }
}

/// The GPU holds each model's patches once and 108 bytes per instance (its
/// record, its roots entry and its visibility word; issue 22 allows 128),
/// beside occlusion culling's parity word and cluster bits (2 per
/// instance, 2 per 32 base patches): the renderer uploads the instance
/// table (not the world patches) and reports its memory so.
#[test]
fn the_gpu_holds_each_model_once() {
    let gpu = common::gpu();
    let path = scene("instances-memory", &["catmark_cube.obj"]);
    let scene = Scene::load(&path).unwrap();
    let (geo, shading) = scene.geometry_and_shading().unwrap();
    let instances = 6; // INSTANCES: five entries, the lattice two copies
    assert_eq!(geo.instances.instances.len(), instances);
    assert_eq!(geo.instances.patches.len(), 6);
    assert_eq!(geo.patches.len(), 6 * instances);
    assert!(geo.instances.places(&geo.patches, &geo.flags, &geo.weights));
    let r = bezier_subdiv::renderer::Renderer::new(
        gpu.arc(),
        &geo,
        &shading,
        "subdiv",
        bezier_subdiv::renderer::RendererOptions {
            size: (64, 64),
            background: [0.0; 4],
            frames_in_flight: 1,
            methods: MethodOptions::new(bezier_subdiv::draw::DrawPath::Mesh),
        },
    )
    .unwrap();
    assert_eq!(r.scene().count as usize, 6 * instances);
    assert_eq!(r.scene().model_patches, 6);
    let memory = r.memory();
    let bytes = |key: &str| memory.iter().find(|(k, _)| *k == key).unwrap().1;
    assert_eq!(bytes("base_patches"), 6 * 196);
    assert_eq!(bytes("shading_patches"), 6 * 288);
    let clusters = cluster_set_words(instances, 6 * instances);
    assert_eq!(clusters, 1);
    assert_eq!(
        bytes("instances"),
        instances as u64 * GPU_BYTES_PER_INSTANCE + 4 + 2 * 4 * clusters as u64
    );
    assert_eq!((INSTANCE_BYTES, GPU_BYTES_PER_INSTANCE), (96, 108));
    gpu.finish();
}
