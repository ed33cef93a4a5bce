//! The tessellation baselines (`tess`, `tess-reparam`) on lavapipe with the
//! validation layer on: both sides of every shared patch edge get the same
//! level and the same vertices, bit for bit; the re-parameterised metric
//! never asks for more than the uniform one; the triangle query counts the
//! tessellator's output; FLIP against the ground truth orders coarse and
//! fine renders; and no holes on the closed models.

mod common;

use bezier_subdiv::constants::*;
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::eval::flip::flip;
use bezier_subdiv::eval::ground_truth_image;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::edges::PatchLevels;
use bezier_subdiv::methods::edges::{check_edge_vertices, check_levels, shared_edges};
use bezier_subdiv::methods::tess::Tess;
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::renderer::Renderer;
use bezier_subdiv::scene::geometry::SceneGeometry;
use bezier_subdiv::vk::PrimitiveQuery;

const SIZE: (u32, u32) = (320, 180);

/// A view of the scene's first camera with culling off, so that every
/// patch is tessellated.
fn unculled(cam: &bezier_subdiv::scene::camera::Camera, eps: f64) -> View {
    let mut v = View::new(cam, SIZE, eps, 0.5, SHADE_NORMAL);
    v.params.flags &= !(FLAG_FRUSTUM_CULL | FLAG_BACKFACE_CULL);
    v
}

fn tess_renderer(gpu: &common::Gpu, geo: &SceneGeometry, method: &str) -> Renderer {
    let mut r = common::renderer(gpu, geo, method, SIZE, MethodOptions::new(DrawPath::Mesh));
    r.capture = true;
    r
}

fn levels(r: &Renderer) -> Vec<PatchLevels> {
    r.method()
        .downcast::<Tess>()
        .unwrap()
        .read_levels(r.context())
        .unwrap()
}

/// Every shared edge of the kitchen's patches gets bit-identical outer
/// levels from both patches, for both metrics and several tolerances; all
/// levels lie in [1, max]. The kitchen has models of every kind: the
/// teapot's collapsed poles, cages with extraordinary vertices, an open
/// model.
#[test]
fn shared_edges_get_equal_levels_from_both_sides() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("kitchen.toml");
    let shared = shared_edges(&geo.patches);
    let max = gpu.info().limits.max_tessellation_generation_level as f32;
    for method in ["tess", "tess-reparam"] {
        let mut r = tess_renderer(&gpu, &geo, method);
        for eps in [0.25, 1.0, 4.0] {
            r.render(&unculled(&s.camera, eps)).unwrap();
            let lv = levels(&r);
            assert_eq!(lv.len(), geo.patches.len());
            let mut above_one = 0;
            for l in &lv {
                assert!(!l.culled);
                for x in l.outer.iter().chain(&l.inner) {
                    assert!((1.0..=max).contains(x), "{method}: level {x}");
                }
                above_one += l.outer.iter().filter(|&&x| x > 1.0).count();
            }
            assert!(above_one > 1000, "{method} ε {eps}: the levels must vary");
            let c = check_levels(&shared, &lv);
            assert!(c.checked > 60_000, "{method} ε {eps}: {c:?}");
            assert_eq!(c.bad, 0, "{method} ε {eps}: {c:?}");
        }
    }
    gpu.finish();
}

/// Both sides of a shared edge place their edge vertices at the same
/// tessellator coordinates (measured along one direction) and evaluate
/// them to the same positions, bit for bit, also where the re-
/// parameterisation moves them: no T-junctions, no cracks. Checked on the
/// kitchen with every patch tessellated.
#[test]
fn shared_edge_vertices_meet_bit_for_bit() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("kitchen.toml");
    let shared = shared_edges(&geo.patches);
    for method in ["tess", "tess-reparam"] {
        let mut r = tess_renderer(&gpu, &geo, method);
        r.render(&unculled(&s.camera, 0.25)).unwrap();
        let tess = r.method().downcast::<Tess>().unwrap();
        let (vertices, total) = tess.read_edge_vertices(r.context()).unwrap();
        assert_eq!(
            vertices.len() as u64,
            total,
            "{method}: the capture overflowed"
        );
        if method == "tess" {
            // Uniform samples: the point of the CPU twin of eval_patch at
            // the shader's parameter, bit for bit.
            for v in &vertices {
                let t = if v.t < 0.5 { 1.0 - (1.0 - v.t) } else { v.t };
                let (u, w) = match v.edge {
                    0 => (0.0, t),
                    1 => (t, 0.0),
                    2 => (1.0, t),
                    _ => (t, 1.0),
                };
                let want = geo.patches[v.patch as usize].eval(u, w);
                assert_eq!(
                    want.to_array().map(f32::to_bits),
                    v.position.map(f32::to_bits),
                    "tess: edge {} of patch {} at {t}",
                    v.edge,
                    v.patch
                );
            }
        }
        let c = check_edge_vertices(&shared, &levels(&r), &vertices);
        println!("{method}: {c:?}");
        assert_eq!(c.bad, 0, "{method}: {c:?}");
        assert!(c.checked > 20_000, "{method}: {c:?}");
    }
    gpu.finish();
}

/// On the kitchen's first camera at ε = 1: per patch, the re-parameterised
/// levels never exceed the uniform ones (the integral of the local density
/// is at most its maximum, and the subdivided mixed bound at most Filip's).
/// The levels drawn are the metric's or above (narrowed border strips add
/// segments), and some strips of the kitchen are narrowed.
#[test]
fn reparam_never_asks_for_more_than_uniform() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("kitchen.toml");
    let size = (960, 540);
    let view = View::new(&s.camera, size, 1.0, 0.5, SHADE_NORMAL);
    let mut counts = Vec::new();
    let mut all = Vec::new();
    for method in ["tess", "tess-reparam"] {
        let mut r = common::renderer(&gpu, &geo, method, size, MethodOptions::new(DrawPath::Mesh));
        r.capture = true;
        let report = r.render(&view).unwrap();
        let (query, n) = report.primitives.expect("a triangle query");
        assert_eq!(query, PrimitiveQuery::Generated);
        assert!(report.stats.culled_patches > 0);
        counts.push(n);
        all.push(levels(&r));
    }
    let (uniform, reparam) = (&all[0], &all[1]);
    let slack = 1.0 + 1e-6;
    let mut lower = 0;
    let mut narrowed = 0;
    for (u, p) in uniform.iter().zip(reparam) {
        assert_eq!(u.culled, p.culled);
        // Narrowed border strips only ever add segments.
        for l in [u, p] {
            assert!(l.drawn_inner[0] >= l.inner[0] && l.drawn_inner[1] >= l.inner[1]);
            narrowed += usize::from(l.drawn_inner != l.inner);
        }
        assert!(p.mixed <= u.mixed * slack, "{} > {}", p.mixed, u.mixed);
        for (a, b) in u
            .outer
            .iter()
            .chain(&u.inner)
            .zip(p.outer.iter().chain(&p.inner))
        {
            assert!(b <= &(a * slack), "reparam level {b} above uniform {a}");
            lower += usize::from(b < a);
        }
    }
    println!(
        "kitchen at 960x540, ε = 1: tess {} triangles, tess-reparam {}; {narrowed} of {} \
         patches' border strips narrowed",
        counts[0],
        counts[1],
        2 * uniform.len()
    );
    assert!(
        lower > 10_000,
        "the re-parameterisation must lower levels ({lower})"
    );
    // Not asserted: fewer triangles drawn. The lower levels leave wider
    // border strips, which the narrowing then pays for with two segments
    // more (kitchen at 640x360: tess 126,264 triangles, tess-reparam
    // 123,893; before the narrowing 113,352 and 95,879, 0.85x;
    // docs/BENCHMARKS.md, "Border strips").
    assert!(narrowed > 0, "no border strip was narrowed");
    gpu.finish();
}

/// FLIP against the ground truth of the same view: the ground truth
/// against itself is 0; a coarse tessellation (ε = 16) scores worse than a
/// fine one (ε = 0.5), for both metrics; and the fine one is close.
#[test]
fn flip_orders_coarse_and_fine_renders() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("teapot.toml");
    let size = (256, 192);
    let mut options = MethodOptions::new(DrawPath::Mesh);
    options.per_method.ground_truth.grid = 32;
    for method in ["tess", "tess-reparam"] {
        let mut r = common::renderer(&gpu, &geo, method, size, options.clone());
        let view = |eps| View::new(&s.camera, size, eps, 0.5, SHADE_NORMAL);
        let reference = ground_truth_image(&mut r, &view(1.0)).unwrap();
        let (w, h) = size;
        assert_eq!(flip(&reference, &reference, w, h).unwrap().mean, 0.0);
        let score = |r: &mut Renderer, eps| {
            r.render(&view(eps)).unwrap();
            flip(&reference, &r.read_image().unwrap(), w, h)
                .unwrap()
                .mean
        };
        let coarse = score(&mut r, 16.0);
        let fine = score(&mut r, 0.5);
        println!("{method}: FLIP coarse {coarse:.5}, fine {fine:.5}");
        assert!(
            0.0 < fine && fine < coarse,
            "{method}: fine {fine}, coarse {coarse}"
        );
        assert!(fine < 0.01, "{method}: fine {fine}");
    }
    gpu.finish();
}

/// `validate --method tess` and `--method tess-reparam`: equal levels and
/// vertices on the shared edges of every keyframe, the hole test on every
/// kitchen model finds nothing, and the validation layer is quiet.
#[test]
fn no_holes_on_the_kitchen_models() {
    let _gpu = common::gpu();
    for method in ["tess", "tess-reparam"] {
        let report = common::validate("kitchen.toml", method, SIZE, true);
        println!("{}", report.table);
        assert!(report.ok(), "{}", report.table);
        let holes = report
            .results
            .iter()
            .filter(|r| r.check.starts_with("holes"))
            .count();
        assert_eq!(
            holes,
            common::distinct_models("kitchen.toml"),
            "{}",
            report.table
        );
        let edges = report
            .results
            .iter()
            .filter(|r| r.check.starts_with("edge") && r.frame.is_some())
            .count();
        assert!(edges >= 4, "{}", report.table);
        assert!(
            report.table.contains("tessellation path"),
            "{}",
            report.table
        );
    }
}

/// Geometric p99 (pixels, off silhouettes) of `method`'s image of `view`
/// against the ground truth's.
fn geometric_p99(r: &mut Renderer, view: &View, cam: &bezier_subdiv::scene::camera::Camera) -> f64 {
    let (w, h) = r.target().size();
    let reference = ground_truth_image(r, view).unwrap();
    r.render(view).unwrap();
    let image = r.read_image().unwrap();
    let errors = flip(&reference, &image, w, h).unwrap().errors;
    bezier_subdiv::eval::geometric_error(r, view, cam, &errors)
        .unwrap()
        .geo_p99_px
}

/// Both metrics keep ε (geometric p99 against the ground truth) in the two
/// cases that broke it (issue 35). The pillow's boundary edges are straight
/// (outer level 1) beside a curved interior (a high inner level): the
/// border strip's triangles spanned the whole edge, p99 1.9–2.8 ε on its
/// keyframes until the strips were narrowed. The teapot at ε 0.15 and
/// 1920x1080 tessellates its lid rim at the device's largest level, where
/// lavapipe drew shards (p99 7.4 px: its 16-bit vertex numbers wrapped)
/// until each draw covered few enough patches; at ε 0.1 more patches
/// reach that level.
#[test]
fn tessellation_keeps_eps_in_border_strips_and_at_the_largest_levels() {
    let gpu = common::gpu();
    let options = MethodOptions::new(DrawPath::Mesh);
    let cases = [
        ("pillow.toml", (960, 540), 0.25, &[0usize, 1][..]),
        ("teapot.toml", (1920, 1080), 0.15, &[0][..]),
        ("teapot.toml", (1920, 1080), 0.1, &[0][..]),
    ];
    for (scene, size, eps, frames) in cases {
        let (s, geo) = common::scene(scene);
        let mut r = common::renderer(&gpu, &geo, "tess", size, options.clone());
        for method in ["tess", "tess-reparam"] {
            r.set_method(method).unwrap();
            for &k in frames {
                let cam = s.frame_camera(k).unwrap();
                let view = View::new(&cam, size, eps, 0.5, SHADE_NORMAL);
                let p99 = geometric_p99(&mut r, &view, &cam);
                println!("{scene} keyframe {k}, {method}, ε {eps}: geometric p99 {p99:.3} px");
                assert!(
                    p99 <= eps,
                    "{scene} keyframe {k}, {method}: p99 {p99} px > ε {eps}"
                );
            }
        }
    }
    gpu.finish();
}
