//! Method `corners`, the worked example of docs/ARCHITECTURE.md ("Adding a
//! method"): it draws every base patch as the two triangles of its corner
//! control points, which is exactly what the ground truth draws with a grid
//! of one cell per patch (its samples at u, v in {0, 1} are the corner
//! points, bit for bit). So the two images must be equal pixel for pixel,
//! on the teapot and on the kitchen (instances, mirrored ones included),
//! and `corners` must draw two triangles per patch its cull pass keeps:
//! the primitive query's count against the visible patches the method
//! read back, culling some of the kitchen's (the equal images show it
//! culls nothing that draws a pixel).

mod common;

use bezier_subdiv::constants::SHADE_NORMAL;
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::{self, MethodOptions};

const SIZE: (u32, u32) = (320, 180);

/// Renders keyframe 0 of `scene` with `method` (and `grid` cells per
/// patch side for the ground truth): the image, the triangles drawn (the
/// primitive query's count) and the patches culled (the method's).
fn draw(gpu: &common::Gpu, scene: &str, method: &str, grid: u32) -> (Vec<u8>, u64, u64) {
    let (s, geo) = common::scene(scene);
    let mut options = MethodOptions::new(DrawPath::Mesh);
    options.per_method.ground_truth.grid = grid;
    let mut r = common::renderer(gpu, &geo, method, SIZE, options);
    let cam = s.frame_camera(0).expect("keyframe 0");
    let report = r
        .render(&View::new(&cam, SIZE, 1.0, 0.5, SHADE_NORMAL))
        .unwrap_or_else(|e| panic!("{scene} with {method}: {e}"));
    let culled = report.stats.culled_patches;
    (r.read_image().unwrap(), report.triangles(), culled)
}

#[test]
fn corners_draws_the_ground_truth_of_one_cell_per_patch() {
    let gpu = common::gpu();
    for scene in ["teapot.toml", "kitchen.toml"] {
        let patches = common::scene(scene).1.patches.len() as u64;
        let (image, triangles, culled) = draw(&gpu, scene, "corners", 64);
        assert_eq!(
            triangles,
            2 * (patches - culled),
            "{scene}: two triangles per patch the cull keeps ({culled} culled)"
        );
        if scene == "kitchen.toml" {
            assert!(culled > 0, "{scene}: the cull kept every patch");
        }
        let (reference, _, _) = draw(&gpu, scene, "ground-truth", 1);
        let background = image.chunks(4).filter(|p| p[..3] == image[..3]).count();
        assert!(
            background < image.len() / 4,
            "{scene}: nothing drawn ({background} background pixels)"
        );
        let differing = image
            .chunks(4)
            .zip(reference.chunks(4))
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(differing, 0, "{scene}: pixels unlike the ground truth's");
    }
    gpu.finish();
}

/// The registry entry declares what the method can draw, and the
/// registry's checks refuse it, by name, the scenes it cannot (rational
/// patches, PN triangles) before any GPU work.
#[test]
fn corners_refuses_what_its_entry_does_not_declare() {
    let info = methods::find("corners").unwrap();
    let (_, teapot) = common::scene("teapot.toml");
    assert!(methods::check_geometry(info, &teapot).is_ok());
    for (scene, what) in [
        ("rational.toml", "cannot draw rational patches"),
        ("pn.toml", "cannot draw PN triangles"),
    ] {
        let (_, geo) = common::scene(scene);
        let err = methods::check_geometry(info, &geo).unwrap_err().to_string();
        assert!(
            err.contains("`corners` ") && err.contains(what),
            "{scene}: {err}"
        );
    }
}
