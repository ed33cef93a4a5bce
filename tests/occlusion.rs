//! Occlusion culling on lavapipe (validation layer on): the level methods
//! draw the instances the last frame saw, build a depth pyramid from them,
//! and test every other instance in view, and each node of those, against
//! it. The image must be the unculled one to the pixel, on the first frame
//! (which culls what its early phase hides) and on the next (whose early
//! phase is the first's verdict), and the hidden work must go: on the herd's
//! keyframe behind the wall most of the cars, and on the kitchen's
//! chessboard and table-top keyframes the models behind the table.

mod common;

use bezier_subdiv::constants::SHADE_NORMAL;
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::renderer::{FrameReport, Renderer};
use bezier_subdiv::scene::file::SceneGeometry;

const SIZE: (u32, u32) = (320, 180);

fn own(report: &FrameReport, key: &str) -> u64 {
    report
        .stats
        .get_u64(key)
        .unwrap_or_else(|| panic!("no `{key}` in {:?}", report.stats.own))
}

/// Pixels of `a` and `b` (RGBA8) that differ.
fn differing(a: &[u8], b: &[u8]) -> usize {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .filter(|(x, y)| x != y)
        .count()
}

/// Draws `view` without occlusion culling and then twice with it, on
/// `method` and `draw` with `samples` samples; asserts the culled images
/// equal the unculled one; returns the unculled frame and the second
/// culled one.
fn culled_and_unculled(
    gpu: &common::Gpu,
    geo: &SceneGeometry,
    method: &str,
    draw: DrawPath,
    samples: u32,
    view: &View,
    what: &str,
) -> (FrameReport, FrameReport) {
    let plain = MethodOptions {
        samples,
        ..MethodOptions::new(draw)
    };
    let mut r: Renderer = common::renderer(gpu, geo, method, SIZE, plain.clone());
    let unculled = r.render(view).unwrap();
    let reference = r.read_image().unwrap();
    r.set_options(MethodOptions {
        occlusion: true,
        ..plain
    })
    .unwrap();
    let mut last = None;
    for frame in 1..=2 {
        let report = r.render(view).unwrap();
        let on = report.stats.own.iter().find(|(k, _)| *k == "occlusion");
        assert_eq!(on.map(|(_, v)| v.clone()), Some(true.into()), "{what}");
        let image = r.read_image().unwrap();
        let n = differing(&image, &reference);
        assert_eq!(n, 0, "{what}, culled frame {frame}: {n} pixels differ");
        last = Some(report);
    }
    (unculled, last.unwrap())
}

/// The herd's keyframe 4, low behind the wall: the far block of cars is
/// hidden. Both kernels, single-sampled and with 4 samples (the pyramid
/// then takes each pixel's farthest sample), and the fallback path, which
/// draws this view's unculled list in chunks (it once refused it) and
/// reports the mesh path's triangles (it once counted its degenerate
/// wedge placeholders too, 2.8 times as many on this view).
#[test]
fn the_herd_behind_the_wall_draws_the_same_image_for_a_fifth_of_the_triangles() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("herd.toml");
    let view = View::new(&s.frame_camera(4).unwrap(), SIZE, 1.0, 0.5, SHADE_NORMAL);
    let mut counts = Vec::new();
    for (method, draw, samples) in [
        ("subdiv", DrawPath::Mesh, 1),
        ("subdiv-indirect", DrawPath::Mesh, 4),
        ("subdiv", DrawPath::Fallback, 1),
    ] {
        let what = format!("herd frame 4, {method} {draw:?} {samples} samples");
        let (unculled, culled) =
            culled_and_unculled(&gpu, &geo, method, draw, samples, &view, &what);
        let (before, after) = (unculled.triangles(), culled.triangles());
        println!(
            "{what}: {before} -> {after} triangles; {} instances hidden ({} patches), {} \
             nodes culled as hidden, {} drawn early",
            own(&culled, "instances_occluded"),
            own(&culled, "instance_occluded_patches"),
            own(&culled, "occluded"),
            own(&culled, "instances_early"),
        );
        assert!(own(&culled, "instances_occluded") > 250, "{what}");
        assert!(after * 3 < before, "{what}: {before} -> {after}");
        // Hidden patches count as culled, never as processed.
        assert!(
            culled.stats.culled_patches >= own(&culled, "instance_occluded_patches"),
            "{what}"
        );
        counts.push((before, after));
    }
    assert_eq!(
        counts[2], counts[0],
        "fallback against mesh: (unculled, culled) triangles"
    );
    gpu.finish();
}

/// The kitchen's keyframes 4 (over the chessboard) and 6 (down on the
/// table top) and 2 (low among the cars): the same image, fewer triangles
/// where something is hidden.
#[test]
fn kitchen_keyframes_draw_the_same_image_with_less_where_something_is_hidden() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("kitchen.toml");
    for (frame, method, draw) in [
        (4, "subdiv", DrawPath::Fallback),
        (6, "subdiv-indirect", DrawPath::Mesh),
        (2, "subdiv-indirect", DrawPath::Fallback),
    ] {
        let view = View::new(
            &s.frame_camera(frame).unwrap(),
            SIZE,
            1.0,
            0.5,
            SHADE_NORMAL,
        );
        let what = format!("kitchen frame {frame}, {method} {draw:?}");
        let (unculled, culled) = culled_and_unculled(&gpu, &geo, method, draw, 1, &view, &what);
        println!(
            "{what}: {} -> {} triangles, {} instances and {} nodes hidden",
            unculled.triangles(),
            culled.triangles(),
            own(&culled, "instances_occluded"),
            own(&culled, "occluded"),
        );
        assert!(culled.triangles() <= unculled.triangles(), "{what}");
        if frame != 2 {
            assert!(
                culled.triangles() * 10 < unculled.triangles() * 9,
                "{what}: the models behind the table are drawn"
            );
        }
    }
    gpu.finish();
}
