//! `subdiv` and `subdiv-indirect` on rational patches (lavapipe, validation
//! on): on scenes/rational.toml (an exact rational torus and sphere beside
//! the polynomial teapot) the GPU's ready set equals the oracle's and every
//! drawn vertex is the oracle's bit for bit, over ε × λ, on both draw paths
//! of both subdivision methods (back-face culling of the one-sided rational
//! models included).

mod common;

use std::path::Path;

use bezier_subdiv::commands::validate::{run, ValidateArgs};
use bezier_subdiv::commands::GpuRequest;
use bezier_subdiv::constants::*;
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::patch::oracle::{subdivide_parallel_weighted, WeightedPatches};
use bezier_subdiv::renderer::Renderer;
use bezier_subdiv::scene::geometry::SceneGeometry;

const SIZE: (u32, u32) = (320, 180);

/// Renders `v`, checks ready set and vertex bits against the oracle, and
/// returns how many ready nodes belong to rational patches and how many
/// nodes the oracle culled as back-facing (only the rational models are
/// one-sided in this scene).
fn check_frame(r: &mut Renderer, geo: &SceneGeometry, v: &View, what: &str) -> (usize, u64) {
    let surfaces = WeightedPatches {
        patches: &geo.patches,
        weights: &geo.weights,
        flags: &geo.flags,
    };
    let (ready, oracle) = common::check_frame(r, v, what, &surfaces, |params| {
        subdivide_parallel_weighted(&geo.patches, &geo.weights, &geo.flags, params, 2)
    });
    let rational = ready
        .iter()
        .filter(|q| geo.flags[q.patch() as usize] & PATCH_RATIONAL != 0)
        .count();
    (rational, oracle.stats.backface_culled)
}

#[test]
fn rational_scene_equals_the_oracle_on_both_paths_and_methods() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("rational.toml");
    assert!(geo.is_rational());
    let runs = [
        ("subdiv", DrawPath::Mesh),
        ("subdiv", DrawPath::Fallback),
        ("subdiv-indirect", DrawPath::Mesh),
        ("subdiv-indirect", DrawPath::Fallback),
    ];
    let (mut rational_nodes, mut backfacing) = (0, 0);
    for (method, path) in runs {
        let mut r = common::renderer(&gpu, &geo, method, SIZE, MethodOptions::new(path));
        r.capture = true;
        for frame in [0, s.frame_count() - 1] {
            let cam = s.frame_camera(frame).unwrap();
            for eps in [0.5, 1.0, 2.0] {
                for lambda in [0.0, 0.5] {
                    let v = View::new(&cam, SIZE, eps, lambda, SHADE_NORMAL);
                    let what = format!("{method} {path:?} frame {frame} eps {eps} lambda {lambda}");
                    let (n, b) = check_frame(&mut r, &geo, &v, &what);
                    rational_nodes += n;
                    backfacing += b;
                }
            }
        }
    }
    assert!(
        rational_nodes > 1000,
        "the views must draw the rational models"
    );
    assert!(
        backfacing > 100,
        "the views must cull rational back faces ({backfacing})"
    );
    gpu.finish();
}

/// The same under 1:2 splits (`--split aniso`): rational nodes split in one
/// direction where their edges are flat in the other, on both methods and
/// paths, equal to the oracle.
#[test]
fn rational_aniso_splits_equal_the_oracle() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("rational.toml");
    let runs = [
        ("subdiv", DrawPath::Mesh),
        ("subdiv-indirect", DrawPath::Fallback),
    ];
    let mut halved = 0;
    for (method, path) in runs {
        let mut r = common::renderer(&gpu, &geo, method, SIZE, MethodOptions::new(path));
        r.capture = true;
        for frame in [0, s.frame_count() - 1] {
            let cam = s.frame_camera(frame).unwrap();
            for lambda in [0.0, 0.5] {
                let mut v = View::new(&cam, SIZE, 1.0, lambda, SHADE_NORMAL);
                v.params.flags |= FLAG_ANISO;
                let what = format!("{method} {path:?} frame {frame} lambda {lambda} aniso");
                check_frame(&mut r, &geo, &v, &what);
                let vp = r.effective_params(&v);
                let oracle =
                    subdivide_parallel_weighted(&geo.patches, &geo.weights, &geo.flags, &vp, 2);
                halved += oracle.ready.iter().filter(|q| q.du() != q.dv()).count();
            }
        }
    }
    assert!(
        halved > 100,
        "the views must split rational nodes 1:2 ({halved})"
    );
    gpu.finish();
}

/// The hole test (against `ground-truth`, which evaluates rational patches
/// too) finds nothing on the rational torus and sphere drawn by `subdiv`,
/// on either draw path.
#[test]
fn rational_models_have_no_holes() {
    let _gpu = common::gpu();
    for draw in ["mesh", "fallback"] {
        let mut gpu =
            GpuRequest::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/rational.toml"));
        gpu.size = SIZE;
        gpu.validation = true;
        gpu.draw = draw.parse().unwrap();
        let report = run(&ValidateArgs {
            gpu,
            frames: vec![0],
            skip_holes: false,
            debug_dir: None,
        })
        .unwrap();
        assert!(report.ok(), "{draw}: {}", report.table);
        let holes: Vec<_> = report
            .results
            .iter()
            .filter(|r| r.check.starts_with("holes rational_"))
            .collect();
        assert_eq!(holes.len(), 2, "{draw}: {}", report.table);
    }
}
