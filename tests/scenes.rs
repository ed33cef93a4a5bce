//! The shipped scene files: they load, have the documented patch counts and
//! valid keyframes, and the oracle sees every model from frame 0.

use std::path::Path;

use bezier_subdiv::constants::PATCH_MODEL_SHIFT;
use bezier_subdiv::patch::oracle::subdivide_parallel;
use bezier_subdiv::scene::file::Scene;

fn check(name: &str, patches: usize, frames: usize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.frame_count(), frames, "{name}: keyframes");
    for k in 0..scene.frame_count() {
        scene.frame_camera(k).unwrap().check().unwrap();
    }
    let geo = scene.geometry().unwrap();
    assert_eq!(geo.patches.len(), patches, "{name}: base patches");
    assert_eq!(
        geo.models
            .iter()
            .map(|m| m.patches_per_instance * m.instances)
            .sum::<usize>(),
        patches
    );
    let vp = scene
        .camera
        .view_params(320, 180, scene.view.eps, scene.view.lambda);
    let res = subdivide_parallel(&geo.patches, &geo.flags, &vp, 2);
    let mut seen = vec![0usize; geo.models.len()];
    for q in &res.ready {
        seen[(geo.flags[q.patch as usize] >> PATCH_MODEL_SHIFT) as usize] += 1;
    }
    for (m, n) in geo.models.iter().zip(&seen) {
        assert!(
            *n > 0,
            "{name}: model '{}' not visible from frame 0",
            m.name
        );
    }
}

#[test]
fn teapot_scene() {
    check("teapot.toml", 32, 4);
}

#[test]
fn kitchen_scene() {
    // The paper's kitchen has 35,940 base patches; ours is built to match.
    check("kitchen.toml", 35_940, 7);
}
