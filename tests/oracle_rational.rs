//! The CPU oracle on rational patches: on the exact rational torus and
//! sphere (closed; the sphere's poles are collapsed edges), both sides of
//! every shared boundary curve rebuild the same homogeneous sub-curve bits,
//! the same edge samples and the same verdict at every depth, and the
//! triangulation is watertight (wedges needed); back-face culling never
//! removes a triangle facing the eye; a rational patch with all weights 1
//! subdivides like the polynomial patch.

mod common;

use glam::{Vec3, Vec4};
use rand::{rngs::SmallRng, Rng, SeedableRng};

use bezier_subdiv::constants::PATCH_RATIONAL;
use bezier_subdiv::patch::bezier::BezierPatch;
use bezier_subdiv::patch::homogeneous::{edge_flat, edge_samples, edge_tolerance2, HomPatch};
use bezier_subdiv::patch::oracle::{
    subdivide, subdivide_weighted, triangulate_surfaces, Triangle, WeightedPatches,
};
use bezier_subdiv::patch::quadnode::{QuadNode, EDGE_PENDING, L_MAX};
use bezier_subdiv::patch::rational::{is_polynomial, RationalPatch, Weights, UNIT_WEIGHTS};
use bezier_subdiv::patch::view::{ViewParams, FLAG_BACKFACE_CULL, FLAG_FRUSTUM_CULL};
use bezier_subdiv::scene::geometry::load_model;
use common::cameras;
use common::edges::{assert_sides_agree, segments, sides, SharedEdge};

const MODELS: &[&str] = &["rational_torus.rbpt", "rational_sphere.rbpt"];

struct Model {
    patches: Vec<BezierPatch>,
    weights: Vec<Weights>,
    flags: Vec<u32>,
}

impl Model {
    fn load(name: &str) -> Self {
        let m = load_model(&common::model_path(name)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(m.weights.len(), m.patches.len(), "{name}: weights");
        let flags = m
            .weights
            .iter()
            .map(|w| if is_polynomial(w) { 0 } else { PATCH_RATIONAL })
            .collect();
        Self {
            patches: m.patches,
            weights: m.weights,
            flags,
        }
    }

    fn hom(&self, k: usize) -> HomPatch {
        HomPatch::of(&RationalPatch::new(self.patches[k], self.weights[k]))
    }

    fn surfaces(&self) -> WeightedPatches<'_> {
        WeightedPatches {
            patches: &self.patches,
            weights: &self.weights,
            flags: &self.flags,
        }
    }
}

fn bits4(c: &[Vec4; 4]) -> [[u32; 4]; 4] {
    c.map(|p| p.to_array().map(f32::to_bits))
}

fn shared_edges(m: &Model) -> Vec<SharedEdge> {
    common::edges::shared_edges(m.patches.len(), |k, e| {
        let c = m.hom(k).edge(e);
        // A collapsed edge (a pole) is not an edge between two patches.
        let p0 = c[0].truncate() / c[0].w;
        if c.iter().all(|q| q.truncate() / q.w == p0) {
            return None;
        }
        Some((bits4(&c), bits4(&[c[3], c[2], c[1], c[0]])))
    })
}

/// The edge tier's samples and both sides of both comparisons, as bits,
/// sorted (the two sides run the curve in opposite directions).
fn edge_terms(c: &[Vec4; 4], vp: &ViewParams) -> Vec<[u32; 11]> {
    common::edges::edge_terms(&edge_samples(c), edge_tolerance2(c, vp), vp)
}

/// Both sides of every shared boundary curve rebuild the same homogeneous
/// sub-curve bits, the same samples and the same edge-tier decision, at
/// every depth.
#[test]
fn shared_edges_decide_identically() {
    let mut rng = SmallRng::seed_from_u64(5);
    for name in MODELS {
        let m = Model::load(name);
        let edges = shared_edges(&m);
        // Closed: every non-collapsed side is shared.
        assert!(
            edges.len() * 2 >= m.patches.len() * 3,
            "{name}: {} shared",
            edges.len()
        );
        let views: Vec<ViewParams> = cameras::around(&m.patches)
            .iter()
            .flat_map(|cam| {
                [(0.5, 0.0), (1.0, 0.5), (2.0, 0.5)]
                    .map(|(eps, lambda)| cam.view_params(640, 360, eps, lambda))
            })
            .collect();
        let (mut checked, mut flat_count) = (0u64, 0u64);
        for se in &edges {
            for l in 0..=L_MAX {
                for k in segments(l, l <= 6, 8, &mut rng) {
                    let (na, nb, ca, cb, cb_aligned) = sides(se, l, k, |q, e| {
                        let (a, b, c, d) = q.domain();
                        m.hom(q.patch() as usize).sub(a, b, c, d).edge(e)
                    });
                    assert_eq!(bits4(&ca), bits4(&cb_aligned), "{name}: {na:?} vs {nb:?}");
                    flat_count +=
                        assert_sides_agree(&ca, &cb, &views, edge_terms, edge_flat, || {
                            format!("{name}: {na:?} vs {nb:?}")
                        });
                    checked += views.len() as u64;
                }
            }
        }
        assert!(
            flat_count > 0 && flat_count < checked,
            "{name}: both outcomes exercised ({flat_count}/{checked})"
        );
    }
}

/// Directed edges of the welded (bitwise-equal positions) triangles not
/// matched by an opposite use; degenerate triangles (at the poles) skipped.
fn open_edges(tris: &[Triangle]) -> usize {
    common::edges::unmatched_edges(tris, |_, _, _| false).len()
}

/// The closed rational models triangulate to watertight, consistently
/// wound meshes; the same runs without wedges leave cracks.
#[test]
fn closed_rational_models_are_watertight_and_need_wedges() {
    for name in MODELS {
        let m = Model::load(name);
        let mut cracked_without = 0;
        let mut deepest = 0;
        for cam in cameras::around(&m.patches) {
            for (eps, lambda) in [(0.5, 0.5), (1.0, 0.0), (2.0, 1.0)] {
                let mut vp = cam.view_params(640, 360, eps, lambda);
                vp.flags &= !(FLAG_FRUSTUM_CULL | FLAG_BACKFACE_CULL);
                let res = subdivide_weighted(&m.patches, &m.weights, &m.flags, &vp);
                deepest = deepest.max(res.stats.max_depth);
                let with = triangulate_surfaces(&m.surfaces(), &res.ready, true);
                assert_eq!(open_edges(&with), 0, "{name}: cracks with wedges on");
                let without = triangulate_surfaces(&m.surfaces(), &res.ready, false);
                cracked_without += (open_edges(&without) > 0) as u32;
            }
        }
        assert!(deepest >= 3, "{name}: the views must subdivide adaptively");
        assert!(cracked_without > 0, "{name}: wedges never needed");
    }
}

/// The teapot's patches flagged rational with all weights 1 subdivide like
/// the polynomial patches (back-face culling off: the rational bound is a
/// different one): the same ready set and counts in every view,
/// and the same vertex bits at every node of depth ≤ 8. Why: the sub-patch
/// control points are the polynomial ones bit for bit with w exactly 1 (the
/// unit test in `homogeneous.rs`), and the Bernstein weights of a cubic sum
/// to exactly 1 in f32 at every parameter k/256, so a vertex divides by
/// w = 1. At some parameters of depth 9 and 10 (46 of them) and at 1/3 the
/// sum rounds to 1 − 1 ulp, so there positions (and the criterion's
/// samples) agree to rounding only. Decisions therefore can differ where a
/// sample lies within an ulp of the threshold: they agree in these views,
/// but at ε = 0.2 (λ 0.5, the first camera) 4 of 6,308 ready nodes differ.
/// (Scenes never meet this: a patch whose weights are all 1 is not flagged
/// `PATCH_RATIONAL` and takes the polynomial path.)
#[test]
fn unit_weights_subdivide_like_the_polynomial_patch() {
    use bezier_subdiv::patch::rational::curve4;
    for k in 0..=256u32 {
        let u = k as f32 / 256.0;
        assert_eq!(curve4(u, &[Vec4::W; 4]).w, 1.0, "k = {k}");
    }
    let patches = load_model(&common::model_path("teapot.bpt"))
        .unwrap()
        .patches;
    let weights = vec![UNIT_WEIGHTS; patches.len()];
    let poly_flags = vec![0u32; patches.len()];
    let rat_flags = vec![PATCH_RATIONAL; patches.len()];
    let (mut nodes, mut exact, mut total) = (0, 0, 0);
    for cam in cameras::around(&patches) {
        for (eps, lambda) in [(0.5, 0.5), (1.0, 0.0), (2.0, 1.0)] {
            let mut vp = cam.view_params(640, 360, eps, lambda);
            vp.flags &= !FLAG_BACKFACE_CULL;
            let poly = subdivide(&patches, &poly_flags, &vp);
            let rat = subdivide_weighted(&patches, &weights, &rat_flags, &vp);
            assert_eq!(
                poly.ready, rat.ready,
                "eps {eps} lambda {lambda}: ready sets"
            );
            assert_eq!(poly.stats, rat.stats);
            nodes += poly.ready.len();
            let surf = WeightedPatches {
                patches: &patches,
                weights: &weights,
                flags: &rat_flags,
            };
            let a = triangulate_surfaces(&patches, &poly.ready, true);
            let b = triangulate_surfaces(&surf, &rat.ready, true);
            for (s, t) in a.iter().zip(&b) {
                for k in 0..3 {
                    if s.node.depth() <= 8 {
                        assert_eq!(s.v[k].to_array(), t.v[k].to_array(), "{:?}", s.node);
                    }
                    let d = (s.v[k] - t.v[k]).abs().max_element();
                    assert!(d <= 4e-7 * s.v[k].abs().max_element().max(1.0), "{d}");
                    exact += (s.v[k] == t.v[k]) as u32;
                    total += 1;
                }
            }
        }
    }
    println!("{nodes} ready nodes; {exact} of {total} vertices bitwise equal");
    assert!(nodes > 1000);
}

/// Back-face culling of rational patches only removes triangles that face
/// away from the eye, wedges included (the closed rational models).
#[test]
fn backface_culling_removes_only_triangles_facing_away() {
    use bezier_subdiv::patch::oracle::process_rational;
    let mut culled = 0;
    for name in MODELS {
        let m = Model::load(name);
        for cam in cameras::around(&m.patches) {
            for eps in [0.5, 2.0] {
                let vp = cam.view_params(640, 360, eps, 0.5);
                let eye = vp.eye.truncate();
                culled += common::culling::culled_face_away(
                    name,
                    m.patches.len() as u32,
                    eye,
                    |q| {
                        let k = q.patch() as usize;
                        let base = RationalPatch::new(m.patches[k], m.weights[k]);
                        process_rational(&base, 0, q, &vp)
                    },
                    |q| triangulate_surfaces(&m.surfaces(), &[q], true),
                );
            }
        }
    }
    assert!(culled > 200, "the views must cull ({culled})");
}

/// The rational back-face bound never culls a sub-patch with a point whose
/// rational normal faces the eye (random nodes of the torus and sphere with
/// their weights perturbed, random eyes, a dense sample grid).
#[test]
fn rational_backface_bound_never_culls_a_visible_part() {
    use bezier_subdiv::patch::homogeneous::back_facing;
    use bezier_subdiv::patch::ops::dot3;
    let mut rng = SmallRng::seed_from_u64(9);
    let models: Vec<Model> = MODELS.iter().map(|n| Model::load(n)).collect();
    let mut culled = 0;
    for _ in 0..10_000 {
        let m = &models[rng.random_range(0..models.len())];
        let k = rng.random_range(0..m.patches.len());
        let mut w = m.weights[k];
        for x in &mut w {
            *x *= rng.random_range(0.05..20.0f32);
        }
        let base = RationalPatch::new(m.patches[k], w);
        let l = rng.random_range(0..=5u32);
        let node = QuadNode::new(
            k as u32,
            (l, rng.random_range(0..1 << l)),
            (l, rng.random_range(0..1 << l)),
            [EDGE_PENDING; 4],
        );
        let (a, b, c, d) = node.domain();
        let sub = HomPatch::of(&base).sub(a, b, c, d);
        let eye = Vec3::new(
            rng.random_range(-4.0..4.0),
            rng.random_range(-4.0..4.0),
            rng.random_range(-4.0..4.0),
        );
        if !back_facing(&sub, eye) {
            continue;
        }
        culled += 1;
        for i in 0..=12 {
            for j in 0..=12 {
                let (u, v) = (a + (b - a) * i as f32 / 12.0, c + (d - c) * j as f32 / 12.0);
                let n = base.normal(u, v);
                let p = base.eval(u, v);
                assert!(
                    dot3(n, p - eye) > 0.0,
                    "front-facing point culled: patch {k} at ({u}, {v}), eye {eye}"
                );
            }
        }
    }
    assert!(culled > 100, "the test must exercise culling ({culled})");
}
