//! `cudatess` (Schwarz and Stamminger's compute tessellation) on lavapipe
//! with the validation layer on, checked on what its frames leave in the
//! GPU buffers: no holes on the closed rational and kitchen models; every
//! shared edge gets the same factor (the largest asked for) and the same
//! vertex bits from both sides, also where neighbours ask for different
//! factors; the GPU scan equals a CPU prefix sum on any length; forward
//! differencing stays within 1e-4 of direct evaluation; frames that
//! overflow small buffers are redone and equal the big-buffer frame; the
//! CPU rational evaluation against independent references.

mod common;

use std::path::Path;

use bezier_subdiv::constants::*;
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::cudatess::checks as ct;
use bezier_subdiv::methods::cudatess::constants::*;
use bezier_subdiv::methods::cudatess::pattern::{Pattern, Place};
use bezier_subdiv::methods::cudatess::scan::scan_on_gpu;
use bezier_subdiv::methods::cudatess::{CudaTess, FrameData};
use bezier_subdiv::methods::edges::{check_edge_vertices, check_levels, shared_edges};
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::patch::bezier::BezierPatch;
use bezier_subdiv::patch::homogeneous::{self, HomPatch};
use bezier_subdiv::patch::rational::{RationalPatch, Weights};
use bezier_subdiv::renderer::Renderer;
use bezier_subdiv::scene::desc::Scene;
use bezier_subdiv::scene::geometry::SceneGeometry;
use glam::{DVec3, DVec4, Vec3};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const SIZE: (u32, u32) = (320, 180);

fn options() -> MethodOptions {
    MethodOptions::new(DrawPath::Mesh)
}

fn ct_renderer(gpu: &common::Gpu, geo: &SceneGeometry, options: MethodOptions) -> Renderer {
    common::renderer(gpu, geo, "cudatess", SIZE, options)
}

/// Keyframe `k` of `scene`, ε pixels; culling off when `culled` is false
/// (every patch then tessellated).
fn view(scene: &Scene, k: usize, eps: f64, culled: bool) -> View {
    let cam = scene.frame_camera(k).unwrap();
    let mut v = View::new(&cam, SIZE, eps, 0.5, SHADE_NORMAL);
    if !culled {
        v.params.flags &= !(FLAG_FRUSTUM_CULL | FLAG_BACKFACE_CULL);
    }
    v
}

fn frame(r: &Renderer) -> FrameData {
    r.method()
        .downcast::<CudaTess>()
        .unwrap()
        .read_frame(r.context())
        .unwrap()
}

/// `validate --method cudatess` on the rational scene (torus, sphere,
/// teapot) and the kitchen (its furniture, cube, teapot, pawn, torus, car):
/// the hole test against ground-truth runs on every model and finds nothing, and every keyframe's
/// edge factors, edge vertices and indices pass; no validation errors.
#[test]
fn no_holes_on_the_rational_and_kitchen_models() {
    let _gpu = common::gpu();
    for scene in ["rational.toml", "kitchen.toml"] {
        let models = common::distinct_models(scene);
        assert!(models >= 3, "{scene}: {models} models");
        let report = common::validate(scene, "cudatess", SIZE, true);
        println!("{}", report.table);
        assert!(report.ok(), "{}", report.table);
        let count = |prefix: &str| {
            report
                .results
                .iter()
                .filter(|r| r.check.starts_with(prefix))
                .count()
        };
        assert_eq!(count("holes"), models, "{}", report.table);
        assert!(count("edge factors") >= 3, "{}", report.table);
        assert_eq!(count("validation layer"), 1, "{}", report.table);
    }
}

/// Shared edges whose drawn sides asked for different factors themselves:
/// the cases where taking the largest matters.
fn edges_with_differing_wishes(geo: &SceneGeometry, f: &FrameData) -> usize {
    shared_edges(&geo.patches)
        .values()
        .filter(|sides| {
            // Edges 0 and 2 run along v (factor n), 1 and 3 along u (m).
            let wishes: Vec<u32> = sides
                .iter()
                .filter_map(|s| {
                    let r = &f.records[s.patch];
                    (!r.culled()).then_some(r.own[(s.edge + 1) % 2])
                })
                .collect();
            wishes.iter().any(|&w| w != wishes[0])
        })
        .count()
}

/// On the GPU's own output: every shared edge drawn by several patches has
/// one factor on all sides, the largest any of them asked for; the
/// vertices along it are the same bits from every side; every patch's
/// indices are its pattern's. Views are chosen so that neighbours ask for
/// different factors (close-ups of the torus's inner rim and the sphere's
/// pole, the kitchen unculled at three tolerances).
#[test]
fn shared_edges_get_equal_factors_and_vertices_from_both_sides() {
    let gpu = common::gpu();
    for (name, views) in [
        (
            "rational.toml",
            vec![
                (0, 1.0, true),
                (1, 1.0, true),
                (2, 0.5, true),
                (1, 4.0, false),
            ],
        ),
        (
            "kitchen.toml",
            vec![(0, 0.25, false), (0, 1.0, false), (1, 4.0, true)],
        ),
    ] {
        let (s, geo) = common::scene(name);
        let shared = shared_edges(&geo.patches);
        let mut r = ct_renderer(&gpu, &geo, options());
        let mut differing = 0;
        for (k, eps, culled) in views {
            r.render(&view(&s, k, eps, culled)).unwrap();
            let f = frame(&r);
            assert_eq!(f.records.len(), geo.patches.len());
            differing += edges_with_differing_wishes(&geo, &f);
            let levels = ct::levels(&f);
            let what = format!("{name} frame {k} ε {eps}");
            let eq = check_levels(&shared, &levels);
            assert!(eq.checked > 20, "{what}: {eq:?}");
            assert_eq!(eq.bad, 0, "{what}: {eq:?}");
            let max = ct::check_max_factors(&shared, &f);
            assert_eq!(max.bad, 0, "{what}: {max:?}");
            let vx = check_edge_vertices(&shared, &levels, &ct::edge_vertices(&f));
            assert!(vx.checked > 100, "{what}: {vx:?}");
            assert_eq!(vx.bad, 0, "{what}: {vx:?}");
            let ix = ct::check_indices(&f);
            assert!(ix.checked > 0, "{what}: {ix:?}");
            assert_eq!(ix.bad, 0, "{what}: {ix:?}");
        }
        assert!(
            differing > 10,
            "{name}: neighbours never asked for different factors"
        );
    }
    gpu.finish();
}

/// The GPU's exclusive scan of (vertex, index) count pairs equals a CPU
/// prefix sum on lengths 0, 1, non-powers of two, exact blocks, lengths one
/// past a block, and lengths that need two and three levels.
#[test]
fn gpu_scan_equals_a_cpu_prefix_sum() {
    let gpu = common::gpu();
    let b = CT_SCAN_BLOCK;
    let mut rng = SmallRng::seed_from_u64(11);
    let mut lengths = vec![0, 1, 2, 3, 7, b - 1, b, b + 1, 3 * b + 5, b * b, b * b + 3];
    lengths.extend((0..3).map(|_| rng.random_range(1..3 * b * b)));
    for len in lengths {
        let input: Vec<[u32; 2]> = (0..len)
            .map(|_| [rng.random_range(0..300), rng.random_range(0..3000)])
            .collect();
        let mut want = Vec::with_capacity(input.len());
        let mut sum = [0u32; 2];
        for x in &input {
            want.push(sum);
            sum = [sum[0].wrapping_add(x[0]), sum[1].wrapping_add(x[1])];
        }
        let got = scan_on_gpu(&gpu, &input).unwrap();
        assert_eq!(got.len(), want.len(), "length {len}");
        if let Some(i) = (0..got.len()).find(|&i| got[i] != want[i]) {
            panic!(
                "length {len}: entry {i} is {:?}, the prefix sum {:?}",
                got[i], want[i]
            );
        }
    }
    gpu.finish();
}

/// The diagonal of the control points' box: the size errors are
/// relative to.
fn extent(p: &BezierPatch) -> f64 {
    let (lo, hi) = BezierPatch::bounds(std::slice::from_ref(p)).unwrap();
    f64::from((hi - lo).length())
}

/// With forward differencing, every interior vertex lies within 1e-4 of
/// the patch's size from the directly evaluated one (rational patches
/// included); corners and edge vertices do not take part and stay
/// bit-identical, so the surface stays closed.
#[test]
fn forward_differences_stay_within_1e4_of_evaluation() {
    let gpu = common::gpu();
    for (name, k, eps) in [
        ("rational.toml", 1, 0.5),
        ("rational.toml", 0, 1.0),
        ("kitchen.toml", 0, 1.0),
    ] {
        let (s, geo) = common::scene(name);
        let mut r = ct_renderer(&gpu, &geo, options());
        let v = view(&s, k, eps, false);
        r.render(&v).unwrap();
        let direct = frame(&r);
        let mut forward = options();
        forward.per_method.cudatess.forward_differencing = true;
        r.set_options(forward).unwrap();
        r.render(&v).unwrap();
        let fd = frame(&r);
        assert_eq!(direct.records, fd.records, "{name}: the same pattern");
        assert_eq!(direct.indices, fd.indices, "{name}");
        let (mut interior, mut moved, mut worst) = (0u64, 0u64, 0.0f64);
        for (id, rec) in direct.records.iter().enumerate() {
            if rec.culled() {
                continue;
            }
            let p = Pattern::new(rec.edges);
            let size = extent(&geo.patches[id]);
            for l in 0..p.vertices {
                let at = (rec.offsets[0] + l) as usize;
                let (a, b) = (direct.vertices[at], fd.vertices[at]);
                assert_eq!(a.word, b.word);
                if !matches!(p.place(l), Place::Interior(..)) {
                    assert_eq!(
                        a.position, b.position,
                        "{name}: patch {id} boundary vertex {l}"
                    );
                    continue;
                }
                interior += 1;
                let d = (Vec3::from(a.position) - Vec3::from(b.position)).length();
                moved += u64::from(d > 0.0);
                worst = worst.max(f64::from(d) / size);
            }
        }
        println!("{name} frame {k}: {interior} interior vertices, {moved} moved, worst {worst:e} of the patch size");
        assert!(interior > 1000, "{name}: {interior} interior vertices");
        assert!(moved > 0, "{name}: forward differencing changed nothing");
        assert!(worst <= 1e-4, "{name}: {worst:e}");
    }
    gpu.finish();
}

/// Frames that do not fit small first buffers are redone with grown ones
/// (vertices alone, indices alone, both), and then equal the frame made
/// with big buffers: the same records, vertices, indices and image.
#[test]
fn overflowing_frames_are_redone_with_grown_buffers() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("rational.toml");
    let v = view(&s, 1, 1.0, true);
    let mut big = ct_renderer(&gpu, &geo, options());
    let report = big.render(&v).unwrap();
    assert_eq!(report.redone, 0);
    let want = frame(&big);
    let want_image = big.read_image().unwrap();
    let (nv, ni) = (want.vertices.len() as u32, want.indices.len() as u32);
    assert!(nv > 1000 && ni > 3000);
    for first in [
        (16, 1 << 18),
        (1 << 16, 16),
        (1, 1),
        (nv - 1, ni - 1),
        (nv, ni),
    ] {
        let mut small = ct_renderer(&gpu, &geo, {
            let mut o = options();
            o.per_method.cudatess.capacity = Some(first);
            o
        });
        let report = small.render(&v).unwrap();
        let fits = first.0 >= nv && first.1 >= ni;
        assert_eq!(
            report.redone == 0,
            fits,
            "{first:?}: redone {}",
            report.redone
        );
        let (cv, ci) = small.method().downcast::<CudaTess>().unwrap().capacities();
        assert!(cv >= nv && ci >= ni, "{first:?}: grown to {cv}, {ci}");
        let got = frame(&small);
        assert_eq!(got.records, want.records, "{first:?}");
        assert_eq!(got.vertices, want.vertices, "{first:?}");
        assert_eq!(got.indices, want.indices, "{first:?}");
        assert!(
            small.read_image().unwrap() == want_image,
            "{first:?}: the image differs"
        );
    }
    gpu.finish();
}

/// A model's patches with their weights.
fn rational_model(file: &str) -> Vec<RationalPatch> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/models")
        .join(file);
    let (patches, weights) = bezier_subdiv::scene::bpt::read_rational(&path).unwrap();
    patches
        .into_iter()
        .zip(weights)
        .map(|(p, w)| RationalPatch::new(p, w))
        .collect()
}

/// de Casteljau in f64 on the homogeneous control points: rows at u, then
/// the column at v, each by repeated linear interpolation (an algorithm
/// independent of the Bernstein sums of `patch::rational`).
fn de_casteljau(p: &RationalPatch, u: f64, v: f64) -> DVec3 {
    let lerp4 = |pts: [DVec4; 4], t: f64| {
        let mut q = pts.to_vec();
        while q.len() > 1 {
            q = q.windows(2).map(|w| w[0] * (1.0 - t) + w[1] * t).collect();
        }
        q[0]
    };
    let hom = |k: usize| {
        let w = f64::from(p.w[k]);
        (p.patch.pts[k].as_dvec3() * w).extend(w)
    };
    let rows = [0, 1, 2, 3].map(|j| lerp4([0, 1, 2, 3].map(|i| hom(4 * j + i)), u));
    let h = lerp4(rows, v);
    h.truncate() / h.w
}

/// A signed distance from an exact surface.
type Quadric = fn(DVec3) -> f64;

fn samples() -> Vec<(f32, f32)> {
    let t = [0.0, 0.05, 0.25, 1.0 / 3.0, 0.5, 0.71, 0.9, 1.0];
    t.iter()
        .flat_map(|&u| t.iter().map(move |&v| (u, v)))
        .collect()
}

/// `patch::rational` against references: f64 de Casteljau on homogeneous
/// points (the exact quadrics and a wavy patch with uneven weights), the
/// exact sphere (|p| = 1) and torus ((ρ - 1)² + z² = 0.35²), the normal
/// against finite differences of the surface (perpendicular to both,
/// pointing the same way as their cross product) and, on the sphere,
/// against the radius.
#[test]
fn rational_evaluation_matches_references() {
    let wavy = RationalPatch::new(
        BezierPatch {
            pts: std::array::from_fn(|k| {
                let (x, y) = ((k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0);
                Vec3::new(x, y, (x * 2.7).sin() * (y * 1.9).cos() * 0.6)
            }),
        },
        std::array::from_fn(|k| 0.3 + (k as f32 * 0.61).sin().abs() * 2.0) as Weights,
    );
    let sphere = rational_model("rational_sphere.rbpt");
    let torus = rational_model("rational_torus.rbpt");
    assert_eq!((sphere.len(), torus.len()), (8, 16));
    // Signed distances from the exact surfaces.
    let on_sphere: Quadric = |p| p.length() - 1.0;
    let on_torus: Quadric = |p| ((p.x.hypot(p.y) - 1.0).powi(2) + p.z * p.z).sqrt() - 0.35;
    let cases: Vec<(&str, &RationalPatch, Option<Quadric>)> = sphere
        .iter()
        .map(|p| ("sphere", p, Some(on_sphere)))
        .chain(torus.iter().map(|p| ("torus", p, Some(on_torus))))
        .chain([("wavy", &wavy, None)])
        .collect();
    for (name, p, surface) in cases {
        for (u, v) in samples() {
            let got = p.eval(u, v).as_dvec3();
            let want = de_casteljau(p, f64::from(u), f64::from(v));
            assert!(
                (got - want).length() < 2e-6,
                "{name} ({u}, {v}): {got} vs {want}"
            );
            if let Some(f) = surface {
                // The control points are f32: the surface is exact to ~1e-7.
                assert!(
                    f(want).abs() < 1e-6,
                    "{name} ({u}, {v}): {} off the quadric",
                    f(want)
                );
            }
            // Normals inside the domain (the sphere's collapsed poles have
            // none on the boundary).
            if !(0.01..0.99).contains(&u) || !(0.01..0.99).contains(&v) {
                continue;
            }
            let h = 1e-4;
            let at = |a: f32, b: f32| de_casteljau(p, f64::from(a), f64::from(b));
            let fu = (at(u + h, v) - at(u - h, v)) / (2.0 * f64::from(h));
            let fv = (at(u, v + h) - at(u, v - h)) / (2.0 * f64::from(h));
            let n = p.normal(u, v).as_dvec3().normalize();
            let fd = fu.cross(fv).normalize();
            assert!(
                n.dot(fd) > 0.9999,
                "{name} ({u}, {v}): normal {n}, differences {fd}"
            );
            if name == "sphere" {
                assert!(
                    n.dot(want.normalize()) > 0.9999,
                    "({u}, {v}): {n} not radial"
                );
            }
        }
    }
}

/// Back-patch culling (the test subdiv and tess make): with frustum
/// culling off, the kitchen's far sides are culled, never a two-sided
/// patch, and turning it off draws them again.
#[test]
fn back_facing_one_sided_polynomial_patches_are_culled() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("kitchen.toml");
    let mut r = ct_renderer(&gpu, &geo, options());
    let mut v = view(&s, 0, 1.0, false);
    v.params.flags |= FLAG_BACKFACE_CULL;
    let on = r.render(&v).unwrap();
    let culled = on.stats.get_u64("backface_culled_patches").unwrap();
    assert!(culled > 1000, "{culled} back-facing patches culled");
    let f = frame(&r);
    for (id, rec) in f.records.iter().enumerate() {
        assert!(
            !rec.culled() || geo.flags[id] & PATCH_TWO_SIDED == 0,
            "patch {id} (flags {}) culled",
            geo.flags[id]
        );
    }
    let n = f.records.iter().filter(|r| r.culled()).count() as u64;
    assert_eq!(n, culled);
    v.params.flags &= !FLAG_BACKFACE_CULL;
    let off = r.render(&v).unwrap();
    assert_eq!(off.stats.get_u64("backface_culled_patches"), Some(0));
    assert!(off.triangles() > on.triangles());
    gpu.finish();
}

/// `geo` with every rational patch replaced by its 8×8 sub-patches (by
/// blossoms): the torus's and sphere's quarter patches are too wide for
/// the interval bound to prove any of them back-facing.
fn split_rational(geo: &SceneGeometry) -> SceneGeometry {
    let mut out = geo.clone();
    (out.patches, out.flags, out.weights) = (Vec::new(), Vec::new(), Vec::new());
    for (k, p) in geo.patches.iter().enumerate() {
        if geo.flags[k] & PATCH_RATIONAL == 0 {
            out.patches.push(*p);
            out.flags.push(geo.flags[k]);
            out.weights.push(geo.weights[k]);
            continue;
        }
        let h = HomPatch::of(&RationalPatch::new(*p, geo.weights[k]));
        for (i, j) in (0..8).flat_map(|i| (0..8).map(move |j| (i, j))) {
            let (a, c) = (i as f32 / 8.0, j as f32 / 8.0);
            let sub = h.sub(a, a + 0.125, c, c + 0.125);
            out.patches.push(BezierPatch {
                pts: std::array::from_fn(|n| sub.point(n % 4, n / 4)),
            });
            out.weights
                .push(std::array::from_fn(|n| sub.at(n % 4, n / 4).w));
            out.flags.push(geo.flags[k]);
        }
    }
    out
}

/// One-sided rational patches are culled by subdiv's homogeneous form of
/// the bound: on the GPU exactly where the CPU twin
/// (`patch::homogeneous::back_facing`) says so, never one with a sample
/// facing the eye, and some of them.
#[test]
fn back_facing_rational_patches_are_culled() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("rational.toml");
    let geo = split_rational(&geo);
    let mut r = ct_renderer(&gpu, &geo, options());
    let mut v = view(&s, 0, 1.0, false);
    v.params.flags |= FLAG_BACKFACE_CULL;
    r.render(&v).unwrap();
    let f = frame(&r);
    let eye = Vec3::from(s.frame_camera(0).unwrap().position.map(|x| x as f32));
    let mut culled = 0;
    for (id, rec) in f.records.iter().enumerate() {
        if geo.flags[id] & PATCH_RATIONAL == 0 {
            continue;
        }
        let p = RationalPatch::new(geo.patches[id], geo.weights[id]);
        let cpu = geo.flags[id] & PATCH_TWO_SIDED == 0
            && homogeneous::back_facing(&HomPatch::of(&p), eye);
        assert_eq!(
            rec.culled(),
            cpu,
            "rational patch {id}: GPU and CPU disagree"
        );
        if !cpu {
            continue;
        }
        culled += 1;
        for (u, v) in samples() {
            // NaN (a pole's vanishing normal) is no evidence.
            let facing = p.normal(u, v).dot(p.eval(u, v) - eye);
            assert!(
                facing.is_nan() || facing >= 0.0,
                "culled patch {id} faces the eye at ({u}, {v})"
            );
        }
    }
    // The interval bound is loose on curved patches: of the 1,536 sub-patches
    // of 11.25° only a few far ones are proven back-facing (6 here).
    assert!(culled >= 5, "only {culled} rational patches culled");
    gpu.finish();
}
