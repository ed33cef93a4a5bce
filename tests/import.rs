//! Model import: `.obj` Catmull–Clark cages → Bézier patches (and the `.bpt`
//! reader's sibling checks live in `src/scene/bpt.rs`).
//!
//! The reference models are read from their copies in `scenes/models/`. The cage topology the tests check
//! against comes from a tiny OBJ reader of their own, not from the importer.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use bezier_subdiv::cage::{obj, ImportedModel};
use bezier_subdiv::patch::bezier::BezierPatch;
use bezier_subdiv::scene::SceneError;
use glam::{DVec3, Vec3};

fn data(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/models");
    let path = dir.join(name);
    assert!(
        path.exists(),
        "reference model {} not found ",
        path.display()
    );
    path
}

fn import(name: &str) -> ImportedModel {
    obj::read(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Positions and faces (0-based vertex indices) straight from `v`/`f` lines.
struct RawCage {
    pos: Vec<DVec3>,
    faces: Vec<Vec<usize>>,
}

fn raw_cage(text: &str) -> RawCage {
    let mut pos = Vec::new();
    let mut faces = Vec::new();
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first() {
            Some(&"v") => {
                let c: Vec<f64> = w[1..4]
                    .iter()
                    .map(|s| s.parse::<f32>().unwrap() as f64)
                    .collect();
                pos.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some(&"f") => faces.push(
                w[1..]
                    .iter()
                    .map(|s| s.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    RawCage { pos, faces }
}

fn raw(name: &str) -> RawCage {
    raw_cage(&std::fs::read_to_string(data(name)).unwrap())
}

fn bits(p: Vec3) -> [u32; 3] {
    p.to_array().map(f32::to_bits)
}

fn curve_bits(c: [Vec3; 4]) -> [[u32; 3]; 4] {
    c.map(bits)
}

fn rev(c: [Vec3; 4]) -> [Vec3; 4] {
    [c[3], c[2], c[1], c[0]]
}

fn d(p: Vec3) -> DVec3 {
    DVec3::new(p.x as f64, p.y as f64, p.z as f64)
}

/// Patch corner at face corner k (v_k sits at (0,0), (1,0), (1,1), (0,1)).
fn corner(p: &BezierPatch, k: usize) -> Vec3 {
    [p.at(0, 0), p.at(3, 0), p.at(3, 3), p.at(0, 3)][k]
}

/// Every pair of quads sharing an edge has the same four boundary control
/// points along it, bit for bit (reversed, since the faces run along the
/// edge in opposite directions); all patches at a vertex share its corner
/// point. Returns the number of boundary edges.
fn check_shared_points(name: &str, cage: &RawCage, patches: &[BezierPatch]) -> usize {
    assert_eq!(patches.len(), cage.faces.len(), "{name}");
    let mut half: HashMap<(usize, usize), (usize, usize)> = HashMap::new();
    for (f, face) in cage.faces.iter().enumerate() {
        assert_eq!(face.len(), 4);
        for k in 0..4 {
            half.insert((face[k], face[(k + 1) % 4]), (f, k));
        }
    }
    let mut boundary = 0;
    for (&(a, b), &(f, k)) in &half {
        // patch.edge(k) runs from face corner k to corner k + 1.
        let mine = patches[f].edge(k);
        assert_eq!(
            curve_bits([mine[0], mine[0], mine[3], mine[3]])[0],
            bits(corner(&patches[f], k))
        );
        match half.get(&(b, a)) {
            Some(&(g, m)) => assert_eq!(
                curve_bits(mine),
                curve_bits(rev(patches[g].edge(m))),
                "{name}: faces {f} and {g} disagree along their shared edge"
            ),
            None => boundary += 1,
        }
    }
    let mut at_vertex: HashMap<usize, [u32; 3]> = HashMap::new();
    for (f, face) in cage.faces.iter().enumerate() {
        for (k, &v) in face.iter().enumerate() {
            let c = bits(corner(&patches[f], k));
            assert_eq!(
                *at_vertex.entry(v).or_insert(c),
                c,
                "{name}: corner point of vertex {v}"
            );
        }
    }
    boundary
}

/// Cage-free watertightness: every patch boundary curve whose reversed
/// endpoints occur as another curve's endpoints matches that curve bit for
/// bit. Returns the number of curves without a partner (open boundary).
fn unmatched_curves(patches: &[BezierPatch]) -> usize {
    type Ends = ([u32; 3], [u32; 3]);
    let mut by_ends: HashMap<Ends, Vec<[Vec3; 4]>> = HashMap::new();
    for p in patches {
        for e in 0..4 {
            let c = p.edge(e);
            by_ends.entry((bits(c[0]), bits(c[3]))).or_default().push(c);
        }
    }
    let mut unmatched = 0;
    for curves in by_ends.values() {
        assert_eq!(
            curves.len(),
            1,
            "two curves run the same way between the same ends"
        );
        let c = curves[0];
        match by_ends.get(&(bits(c[3]), bits(c[0]))) {
            Some(other) => assert_eq!(curve_bits(rev(other[0])), curve_bits(c)),
            None => unmatched += 1,
        }
    }
    unmatched
}

/// (1/3)∮ p·n dA over all patches: the enclosed volume, positive when the
/// normals ∂S/∂u × ∂S/∂v point out of a closed surface.
fn signed_volume(patches: &[BezierPatch]) -> f64 {
    let n = 16;
    let mut v = 0.0;
    for p in patches {
        for j in 0..n {
            for i in 0..n {
                let (u, w) = ((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (su, sv) = p.partials(u, w);
                v += d(p.eval(u, w)).dot(d(su).cross(d(sv)));
            }
        }
    }
    v / (3.0 * (n * n) as f64)
}

fn model_size(patches: &[BezierPatch]) -> f64 {
    let mut lo = DVec3::splat(f64::MAX);
    let mut hi = DVec3::splat(f64::MIN);
    for p in patches.iter().flat_map(|p| p.pts.iter()) {
        lo = lo.min(d(*p));
        hi = hi.max(d(*p));
    }
    (hi - lo).length()
}

#[test]
fn reference_models_are_watertight_bit_for_bit() {
    // Boundary edges as found in the data: the pawn is open at the bottom (a
    // ring of 24 edges at z = 0.026), the car has 11 holes (60 edges).
    for (name, count, boundary_edges) in [
        ("catmark_torus.obj", 32, 0),
        ("catmark_cube.obj", 6, 0),
        ("catmark_pawn.obj", 588, 24),
        ("catmark_car.obj", 1575, 60),
    ] {
        let model = import(name);
        let cage = raw(name);
        assert_eq!(model.patches.len(), count, "{name}");
        assert_eq!(model.origins.len(), count, "{name}");
        for (f, o) in model.origins.iter().enumerate() {
            assert_eq!(o.face, f);
            assert_eq!(
                o.corners_uv,
                Some([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
            );
        }
        assert!(model.patches.iter().all(|p| p.is_finite()));
        let boundary = check_shared_points(name, &cage, &model.patches);
        assert_eq!(unmatched_curves(&model.patches), boundary, "{name}");
        assert_eq!(boundary, boundary_edges, "{name}");
        // Outward normals: the enclosed volume is positive. The pawn's and
        // the car's openings are small, so the flux missing through them
        // cannot flip the sign (reversed normals give exactly the negative).
        let volume = signed_volume(&model.patches);
        assert!(volume > 0.0, "{name} is inside out: volume {volume}");
    }
}

/// The conversion rules of `obj.rs`, re-derived by brute force from the raw
/// face list (no half-edges): each control point near a face corner from the
/// corner's own neighbourhood. Corner points of interior vertices are taken
/// as the average of the interior points around the vertex, which is the
/// limit-position formula the importer uses, written another way.
fn acc_by_brute_force(cage: &RawCage) -> Vec<[DVec3; 16]> {
    let p = &cage.pos;
    let mut around: Vec<Vec<Vec<usize>>> = vec![Vec::new(); p.len()];
    let mut edge_faces: HashMap<(usize, usize), usize> = HashMap::new();
    for face in &cage.faces {
        for (k, &v) in face.iter().enumerate() {
            around[v].push(from(face, v));
            let w = face[(k + 1) % face.len()];
            *edge_faces.entry((v.min(w), v.max(w))).or_default() += 1;
        }
    }
    let faces_on = |a: usize, b: usize| edge_faces[&(a.min(b), a.max(b))];
    let boundary_nbrs = |v: usize| -> Vec<usize> {
        let mut n: Vec<usize> = around[v].iter().flat_map(|g| [g[1], g[3]]).collect();
        n.sort_unstable();
        n.dedup();
        n.into_iter().filter(|&w| faces_on(v, w) == 1).collect()
    };
    let valence = |v: usize| {
        let mut n: Vec<usize> = around[v].iter().flat_map(|g| [g[1], g[3]]).collect();
        n.sort_unstable();
        n.dedup();
        n.len()
    };
    // Interior point of face g (rotated to start at v) near v.
    let interior = |g: &[usize]| {
        let v = g[0];
        let n = if boundary_nbrs(v).is_empty() {
            valence(v) as f64
        } else {
            4.0
        };
        (p[v] * n + p[g[1]] * 2.0 + p[g[3]] * 2.0 + p[g[2]]) / (n + 5.0)
    };
    let corner = |v: usize| {
        let b = boundary_nbrs(v);
        match b.len() {
            0 => around[v].iter().map(|g| interior(g)).sum::<DVec3>() / around[v].len() as f64,
            2 if around[v].len() == 1 => p[v],
            2 => (p[b[0]] + p[v] * 4.0 + p[b[1]]) / 6.0,
            _ => panic!("vertex {v} has {} boundary edges", b.len()),
        }
    };
    let edge = |v: usize, w: usize| {
        if faces_on(v, w) == 1 {
            (p[v] * 2.0 + p[w]) / 3.0
        } else {
            let near: Vec<DVec3> = around[v]
                .iter()
                .filter(|g| g.contains(&w))
                .map(|g| interior(g))
                .collect();
            assert_eq!(near.len(), 2);
            (near[0] + near[1]) / 2.0
        }
    };
    const CORNER_AT: [(i32, i32); 4] = [(0, 0), (3, 0), (3, 3), (0, 3)];
    let slot = |(i, j): (i32, i32)| (4 * j + i) as usize;
    cage.faces
        .iter()
        .map(|face| {
            let mut out = [DVec3::NAN; 16];
            for k in 0..4 {
                let (c, next, prev) =
                    (CORNER_AT[k], CORNER_AT[(k + 1) % 4], CORNER_AT[(k + 3) % 4]);
                let step = |to: (i32, i32)| ((to.0 - c.0) / 3, (to.1 - c.1) / 3);
                let (a, b) = (step(next), step(prev));
                let v = face[k];
                out[slot(c)] = corner(v);
                out[slot((c.0 + a.0, c.1 + a.1))] = edge(v, face[(k + 1) % 4]);
                out[slot((c.0 + b.0, c.1 + b.1))] = edge(v, face[(k + 3) % 4]);
                out[slot((c.0 + a.0 + b.0, c.1 + a.1 + b.1))] = interior(&from(face, v));
            }
            out
        })
        .collect()
}

/// The brute force knows the rules for smooth cages with creased boundaries,
/// so the models are read without their crease tags here; creases are
/// checked against OpenSubdiv itself in tests/osd_reference.rs.
#[test]
fn patches_follow_the_conversion_rules_on_every_model() {
    for name in [
        "catmark_torus.obj",
        "catmark_cube.obj",
        "catmark_pawn.obj",
        "catmark_car.obj",
    ] {
        let text = std::fs::read_to_string(data(name)).unwrap();
        let untagged: String = text
            .lines()
            .filter(|l| !l.starts_with("t "))
            .map(|l| format!("{l}\n"))
            .collect();
        let model = obj::parse(Path::new(name), &untagged).unwrap();
        let expected = acc_by_brute_force(&raw(name));
        let tol = 1e-6 * model_size(&model.patches);
        for (f, (patch, want)) in model.patches.iter().zip(&expected).enumerate() {
            for (s, (got, want)) in patch.pts.iter().zip(want).enumerate() {
                assert!(
                    (d(*got) - *want).length() <= tol,
                    "{name}: face {f} point {s}: {got} vs {want}"
                );
            }
        }
    }
}

/// Uniform cubic B-spline basis.
fn bspline_basis(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        s * s * s / 6.0,
        (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
        (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
        t * t * t / 6.0,
    ]
}

/// The face other than `not` that contains all of `vs`.
fn face_with(cage: &RawCage, not: usize, vs: &[usize]) -> Vec<usize> {
    let found: Vec<&Vec<usize>> = cage
        .faces
        .iter()
        .enumerate()
        .filter(|&(g, face)| g != not && vs.iter().all(|v| face.contains(v)))
        .map(|(_, face)| face)
        .collect();
    assert_eq!(found.len(), 1, "looking for a face with {vs:?}");
    found[0].clone()
}

/// `face` rotated to start at `v`.
fn from(face: &[usize], v: usize) -> Vec<usize> {
    let k = face.iter().position(|&x| x == v).unwrap();
    (0..face.len())
        .map(|i| face[(k + i) % face.len()])
        .collect()
}

/// The 4×4 B-spline control net `net[r][c]` (r along v, c along u) of a
/// regular quad: the quad itself in the middle, its neighbours around it.
fn one_ring(cage: &RawCage, f: usize) -> [[usize; 4]; 4] {
    let q = &cage.faces[f];
    let mut net = [[usize::MAX; 4]; 4];
    net[1][1] = q[0];
    net[1][2] = q[1];
    net[2][2] = q[2];
    net[2][1] = q[3];
    // Across edge (a, b) the neighbour reads [b, a, x, y], x next to a.
    let across = |a: usize, b: usize| {
        let g = from(&face_with(cage, f, &[a, b]), b);
        assert_eq!(g[1], a, "neighbour runs the edge the other way");
        (g[2], g[3])
    };
    (net[0][1], net[0][2]) = across(q[0], q[1]);
    (net[1][3], net[2][3]) = across(q[1], q[2]);
    (net[3][2], net[3][1]) = across(q[2], q[3]);
    (net[2][0], net[1][0]) = across(q[3], q[0]);
    let diagonal = |v: usize, a: usize, b: usize| from(&face_with(cage, f, &[v, a, b]), v)[2];
    net[0][0] = diagonal(net[1][1], net[0][1], net[1][0]);
    net[0][3] = diagonal(net[1][2], net[0][2], net[1][3]);
    net[3][3] = diagonal(net[2][2], net[2][3], net[3][2]);
    net[3][0] = diagonal(net[2][1], net[3][1], net[2][0]);
    net
}

#[test]
fn torus_patches_are_the_bspline_patches_of_their_one_rings() {
    let model = import("catmark_torus.obj");
    let cage = raw("catmark_torus.obj");
    let size = model_size(&model.patches);
    let mut worst: f64 = 0.0;
    for (f, patch) in model.patches.iter().enumerate() {
        let net = one_ring(&cage, f);
        for j in 0..=8 {
            for i in 0..=8 {
                let (u, v) = (i as f64 / 8.0, j as f64 / 8.0);
                let (bu, bv) = (bspline_basis(u), bspline_basis(v));
                let mut s = DVec3::ZERO;
                for r in 0..4 {
                    for c in 0..4 {
                        s += cage.pos[net[r][c]] * (bv[r] * bu[c]);
                    }
                }
                let got = d(patch.eval(u as f32, v as f32));
                worst = worst.max((got - s).length() / size);
            }
        }
    }
    assert!(worst < 1e-5, "worst deviation {worst:e} of the model size");
}

#[test]
fn cube_corners_are_limit_positions_and_the_cube_is_closed_and_outward() {
    let model = import("catmark_cube.obj");
    let cage = raw("catmark_cube.obj");
    assert_eq!(model.patches.len(), 6);
    assert_eq!(unmatched_curves(&model.patches), 0);
    let size = model_size(&model.patches);
    // Catmull–Clark limit position at a valence-3 vertex:
    // (9 v + 4 Σ edge neighbours + Σ diagonal vertices) / 24.
    for (f, face) in cage.faces.iter().enumerate() {
        for (k, &v) in face.iter().enumerate() {
            let ring: Vec<Vec<usize>> = cage
                .faces
                .iter()
                .filter(|g| g.contains(&v))
                .map(|g| from(g, v))
                .collect();
            assert_eq!(ring.len(), 3);
            let edges: DVec3 = ring.iter().map(|g| cage.pos[g[1]]).sum();
            let diagonals: DVec3 = ring.iter().map(|g| cage.pos[g[2]]).sum();
            let limit = (cage.pos[v] * 9.0 + edges * 4.0 + diagonals) / 24.0;
            let got = d(corner(&model.patches[f], k));
            assert!(
                (got - limit).length() < 1e-6 * size,
                "face {f} corner {k}: {got} vs {limit}"
            );
        }
    }
    let centre: DVec3 = cage.pos.iter().sum::<DVec3>() / cage.pos.len() as f64;
    for (f, p) in model.patches.iter().enumerate() {
        let n = d(p.normal(0.5, 0.5));
        assert!(
            n.dot(d(p.eval(0.5, 0.5)) - centre) > 0.0,
            "patch {f} faces inwards"
        );
    }
    assert!(signed_volume(&model.patches) > 0.0);
}

const TETRAHEDRON: &str = "\
v 1 1 1
v 1 -1 -1
v -1 1 -1
v -1 -1 1
f 1 2 3
f 1 3 4
f 1 4 2
f 2 4 3
";

const PRISM: &str = "\
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
v 1 0 1
v 0 1 1
f 1 3 2
f 4 5 6
f 1 2 5 4
f 2 3 6 5
f 3 1 4 6
";

/// `corners_uv` of sub-quad k of a refined quad face.
const SUB_QUAD_UV: [[[f32; 2]; 4]; 4] = [
    [[0.0, 0.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]],
    [[1.0, 0.0], [1.0, 0.5], [0.5, 0.5], [0.5, 0.0]],
    [[1.0, 1.0], [0.5, 1.0], [0.5, 0.5], [1.0, 0.5]],
    [[0.0, 1.0], [0.0, 0.5], [0.5, 0.5], [0.5, 1.0]],
];

fn check_convex_and_outward(name: &str, model: &ImportedModel, cage: &RawCage) {
    let centre: DVec3 = cage.pos.iter().sum::<DVec3>() / cage.pos.len() as f64;
    for (k, p) in model.patches.iter().enumerate() {
        let n = d(p.normal(0.5, 0.5));
        assert!(
            n.dot(d(p.eval(0.5, 0.5)) - centre) > 0.0,
            "{name}: patch {k} faces inwards"
        );
    }
    assert!(signed_volume(&model.patches) > 0.0, "{name}");
}

#[test]
fn tetrahedron_refines_then_converts() {
    let model = obj::parse(Path::new("tetra.obj"), TETRAHEDRON).unwrap();
    assert_eq!(model.patches.len(), 12);
    let faces: Vec<usize> = model.origins.iter().map(|o| o.face).collect();
    assert_eq!(faces, vec![0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3]);
    assert!(model.origins.iter().all(|o| o.corners_uv.is_none()));
    assert_eq!(unmatched_curves(&model.patches), 0);
    check_convex_and_outward("tetra", &model, &raw_cage(TETRAHEDRON));
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("4 non-quad faces") && w.contains("12 patches")),
        "{:?}",
        model.warnings
    );
}

#[test]
fn prism_refines_with_quad_origins() {
    let model = obj::parse(Path::new("prism.obj"), PRISM).unwrap();
    assert_eq!(model.patches.len(), 3 + 3 + 4 * 3);
    assert_eq!(unmatched_curves(&model.patches), 0);
    check_convex_and_outward("prism", &model, &raw_cage(PRISM));
    for (k, o) in model.origins.iter().enumerate() {
        match k {
            0..=2 => assert_eq!((o.face, o.corners_uv), (0, None)),
            3..=5 => assert_eq!((o.face, o.corners_uv), (1, None)),
            _ => {
                let (face, sub) = (2 + (k - 6) / 4, (k - 6) % 4);
                assert_eq!((o.face, o.corners_uv), (face, Some(SUB_QUAD_UV[sub])));
            }
        }
    }
}

#[test]
fn quad_and_triangle_give_expected_origins() {
    // A unit quad and a triangle sharing its right edge, both facing +z.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0.5 0\nf 1 2 3 4\nf 2 5 3\n";
    let model = obj::parse(Path::new("mixed.obj"), text).unwrap();
    assert_eq!(model.patches.len(), 7);
    let cage = raw_cage(text);
    for (k, o) in model.origins.iter().enumerate() {
        if k < 4 {
            assert_eq!((o.face, o.corners_uv), (0, Some(SUB_QUAD_UV[k])));
            // The patch's (0,0) corner lies nearest the quad's corner k, its
            // (1,1) corner at the quad's centre.
            let c0 = d(model.patches[k].at(0, 0));
            let nearest = (0..5)
                .min_by(|&a, &b| {
                    (cage.pos[a] - c0)
                        .length()
                        .total_cmp(&(cage.pos[b] - c0).length())
                })
                .unwrap();
            assert_eq!(nearest, cage.faces[0][k]);
            let c2 = d(model.patches[k].at(3, 3));
            assert!((c2 - DVec3::new(0.5, 0.5, 0.0)).length() < 0.2, "{c2}");
        } else {
            assert_eq!((o.face, o.corners_uv), (1, None));
        }
        assert!(
            model.patches[k].normal(0.5, 0.5).z > 0.0,
            "patch {k} faces down"
        );
    }
    // Open surface: everything inside matches, the outline does not.
    assert_eq!(unmatched_curves(&model.patches), 2 * 5);
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("1 non-quad faces")),
        "{:?}",
        model.warnings
    );
}

#[test]
fn pawn_reads_its_crease_tags_and_warns_about_none() {
    let model = import("catmark_pawn.obj");
    let info = model.cage.as_ref().unwrap();
    assert_eq!(
        (info.sharp_edges, info.semi_sharp_edges, info.corners),
        (0, 120, 0)
    );
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    // A tag the converter does not know is named once, with its first line.
    let text = std::fs::read_to_string(data("catmark_pawn.obj")).unwrap()
        + "t vertexedit 0/0/1 x\nt facevaryingpropagatecorners 1/0/0 1\nt vertexedit 0/0/1 y\n";
    let lines = text.lines().count();
    let model = obj::parse(Path::new("pawn.obj"), &text).unwrap();
    assert_eq!(model.warnings.len(), 1, "{:?}", model.warnings);
    assert!(
        model.warnings[0].contains(&format!("`vertexedit` ×2 (first at line {})", lines - 2))
            && model.warnings[0].contains("`facevaryingpropagatecorners` ×1"),
        "{}",
        model.warnings[0]
    );
    // The scheme's tags are read, and two that disagree are refused.
    let text = std::fs::read_to_string(data("catmark_pawn.obj")).unwrap()
        + "t creasemethod 0/0/1 chaikin\nt smoothtriangles 0/0/1 smooth\n";
    let info = obj::parse(Path::new("pawn.obj"), &text)
        .unwrap()
        .cage
        .unwrap();
    assert!(info.scheme.chaikin && info.scheme.smooth_triangles);
    let text = text + "t creasemethod 0/0/1 normal\n";
    let e = obj::parse(Path::new("pawn.obj"), &text)
        .unwrap_err()
        .to_string();
    assert!(e.contains("the opposite at line"), "{e}");
    // Torus has no tags and no warnings at all.
    assert!(import("catmark_torus.obj").warnings.is_empty());
}

#[test]
fn groups_are_joined_into_one_cage() {
    let text = std::fs::read_to_string(data("catmark_cube.obj")).unwrap();
    let mut grouped = String::new();
    let mut faces = 0;
    for line in text.lines() {
        if line.starts_with("f ") {
            grouped += &format!("g part{faces}\n");
            faces += 1;
        }
        grouped += line;
        grouped += "\n";
    }
    let plain = obj::parse(Path::new("cube.obj"), &text).unwrap();
    let joined = obj::parse(Path::new("grouped.obj"), &grouped).unwrap();
    assert_eq!(plain.patches.len(), joined.patches.len());
    for (a, b) in plain.patches.iter().zip(&joined.patches) {
        assert_eq!(a.pts.map(bits), b.pts.map(bits));
    }
    assert!(
        joined
            .warnings
            .iter()
            .any(|w| w.contains("6 objects/groups joined")),
        "{:?}",
        joined.warnings
    );
}

/// A parse error at `line` of `name` whose message contains `needle`.
fn expect_error(name: &str, text: &str, line: Option<usize>, needle: &str) {
    let path = Path::new(name);
    let err = obj::parse(path, text).expect_err(name);
    let shown = err.to_string();
    match (&err, line) {
        (
            SceneError::Parse {
                path: p, line: l, ..
            },
            Some(want),
        ) => {
            assert_eq!((p.as_path(), *l), (path, want), "{name}: {shown}")
        }
        (SceneError::Invalid { path: p, .. }, None) => assert_eq!(p.as_path(), path),
        _ => panic!("{name}: unexpected error kind for line {line:?}: {shown}"),
    }
    assert!(shown.starts_with(name), "{shown}");
    assert!(
        shown.contains(needle),
        "{name}: wanted {needle:?} in {shown}"
    );
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

fn quad_with(line: usize, replacement: &str) -> String {
    let mut lines: Vec<&str> = QUAD.lines().collect();
    lines[line - 1] = replacement;
    lines.join("\n") + "\n"
}

#[test]
fn bad_obj_inputs_are_refused_with_file_and_line() {
    assert!(obj::parse(Path::new("quad.obj"), QUAD).is_ok());
    expect_error("empty.obj", "", None, "empty file");
    expect_error("comments.obj", "# nothing\nv 1 2 3\n", None, "no faces");
    expect_error(
        "word.obj",
        &quad_with(2, "v 1 zero 0"),
        Some(2),
        "not a number",
    );
    expect_error("short-v.obj", &quad_with(3, "v 1 1"), Some(3), "x y z");
    expect_error(
        "nan.obj",
        &quad_with(2, "v 1 NaN 0"),
        Some(2),
        "NaN or infinite",
    );
    expect_error(
        "inf.obj",
        &quad_with(4, "v inf 1 0"),
        Some(4),
        "NaN or infinite",
    );
    expect_error(
        "huge.obj",
        &quad_with(4, "v 1e39 1 0"),
        Some(4),
        "NaN or infinite",
    );
    // Finite, but past what a scene (and a .bpt) accepts (issue 35: it was
    // accepted, and `--out x.bpt` then failed naming a temporary file).
    expect_error(
        "far.obj",
        &quad_with(3, "v 1e30 1 0"),
        Some(3),
        "beyond ±1e6",
    );
    expect_error("w0.obj", &quad_with(4, "v 1 1 0 0"), Some(4), "w is 0");
    expect_error(
        "range.obj",
        &quad_with(5, "f 1 2 3 5"),
        Some(5),
        "index 5 out of range: the file has 4 vertices",
    );
    expect_error(
        "texture-range.obj",
        &quad_with(5, "f 1/1 2/1 3/1 4/3\nvt 0 0\nvt 1 0"),
        Some(5),
        "the file has 2 texture coordinates",
    );
    expect_error("zero.obj", &quad_with(5, "f 0 2 3 4"), Some(5), "index 0");
    expect_error(
        "relative.obj",
        &quad_with(5, "f -1 -2 -3 -5"),
        Some(5),
        "out of range",
    );
    expect_error(
        "garbled-f.obj",
        &quad_with(5, "f 1 2 x 4"),
        Some(5),
        "not a number",
    );
    expect_error("two.obj", &quad_with(5, "f 1 2"), Some(5), "at least 3");
    expect_error("line.obj", &quad_with(5, "l 1 2"), Some(5), "polyline");
    expect_error(
        "vt.obj",
        &quad_with(5, "f 1/1 2/1 3/1 4/9\nvt 0 0"),
        Some(5),
        "texture",
    );
    // Texture coordinates on some corners of a face, or on some faces
    // only (issue 39's bad input): the model imports without them, and a
    // warning names the face's line and says so.
    for (name, text, needle) in [
        (
            "some-corners.obj",
            quad_with(5, "f 1/1 2/2 3 4/1\nvt 0 0\nvt 1 0"),
            "line 5: the face has texture coordinates on 3 of its 4 corners",
        ),
        (
            "some-faces.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nvt 0 0\n\
             f 1/1 2/1 3/1 4/1\nf 2 5 6 3\n"
                .to_string(),
            "line 9: this face has no texture coordinates, but 1 of the 2 faces do",
        ),
    ] {
        let m = obj::parse(Path::new(name), &text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            m.uvs.is_none() && m.cage.as_ref().unwrap().uv.is_none(),
            "{name}"
        );
        assert_eq!(m.patches.len(), text.matches("\nf ").count(), "{name}");
        assert!(
            m.warnings
                .iter()
                .any(|w| w.starts_with("texture coordinates ignored") && w.contains(needle)),
            "{name}: {:?}",
            m.warnings
        );
    }
    expect_error(
        "vt-nan.obj",
        &quad_with(5, "f 1/1 2/1 3/1 4/1\nvt NaN 0"),
        Some(6),
        "`vt` coordinate is NaN",
    );
    // Three faces on one edge used to be refused; they are now three sheets
    // (tests/creases.rs).
    let fan3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
    assert_eq!(
        obj::parse(Path::new("fan3.obj"), fan3)
            .unwrap()
            .patches
            .len(),
        9
    );
    // Faces that repeat a vertex and faces wound against their neighbours
    // used to be refused; OpenSubdiv reads them as non-manifold edges, and
    // so does the importer now (tests/creases.rs).
    let flipped = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 3 4\nf 2 3 5\n";
    let model = obj::parse(Path::new("flipped.obj"), flipped).unwrap();
    assert!(
        model.warnings[0].contains("1 whose two faces run them the same way"),
        "{:?}",
        model.warnings
    );
    let model = obj::parse(Path::new("degenerate.obj"), &quad_with(5, "f 1 2 3 2")).unwrap();
    assert!(
        model.warnings[0].contains("non-manifold"),
        "{:?}",
        model.warnings
    );
    // Relative indices and v/vt/vn references that are fine.
    let ok = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf -4/1/1 -3/1/1 -2//1 -1\n";
    assert_eq!(
        obj::parse(Path::new("relative-ok.obj"), ok)
            .unwrap()
            .patches
            .len(),
        1
    );
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let path = std::env::temp_dir().join("bezier-subdiv-no-such-cage.obj");
    let err = obj::read(&path).unwrap_err();
    assert!(matches!(&err, SceneError::Io { path: p, .. } if *p == path));
    assert!(err.to_string().contains("bezier-subdiv-no-such-cage.obj"));
}

/// Random damage to a small cage: errors are fine, panics are not, and what
/// loads is finite.
#[test]
fn mangled_cages_never_panic() {
    use rand::{rngs::SmallRng, SeedableRng};
    let base = format!("{}g a\n{}", PRISM, "t crease 2/1/0 1 2 3.0\n");
    let alphabet = b"0123456789 -./\nvftgl#eNaI";
    let mut rng = SmallRng::seed_from_u64(11);
    let mut loaded = 0;
    for _ in 0..3000 {
        let text = common::fuzz::mangle(&mut rng, &base, alphabet);
        if let Ok(m) = obj::parse(Path::new("fuzz.obj"), &text) {
            assert!(m.patches.iter().all(|p| p.is_finite()));
            assert_eq!(m.patches.len(), m.origins.len());
            loaded += 1;
        }
    }
    assert!(loaded > 0);
    // With texture coordinates, seams and a triangle (issue 39): no panic,
    // and UV patches, when there are any, one per patch and finite.
    let base = two_quads(true) + "v 1 2 0\nvt 0.7 0.9\nf 3/8 6/6 7/9\n";
    let alphabet = b"0123456789 -./\nvftgl#eNaI";
    let mut loaded = 0;
    for _ in 0..3000 {
        let text = common::fuzz::mangle(&mut rng, &base, alphabet);
        if let Ok(m) = obj::parse(Path::new("fuzz-uv.obj"), &text) {
            if let Some(uv) = &m.uv_patches {
                assert_eq!(uv.patches.len(), m.patches.len(), "{text}");
                assert!(
                    uv.patches.iter().flatten().flatten().all(|c| c.is_finite()),
                    "{text}"
                );
                loaded += 1;
            }
        }
    }
    assert!(loaded > 0);
}

/// Two quads side by side (vertices 2 and 3 shared), their texture
/// coordinates continuous (`vt` = `v`) or cut along the shared edge.
fn two_quads(cut: bool) -> String {
    let right = if cut {
        "f 2/7 5/5 6/6 3/8"
    } else {
        "f 2/2 5/5 6/6 3/3"
    };
    let mut s = String::from("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n");
    for uv in [
        "0 0", "0.5 0", "0.5 1", "0 1", "1 0", "1 1", "0.5 0", "0.5 1",
    ] {
        s += &format!("vt {uv}\n");
    }
    s + "f 1/1 2/2 3/3 4/4\n" + right + "\n"
}

/// A cage's texture coordinates are read per face corner and its seams
/// found by `vt` index (OpenSubdiv's face-varying topology), also where
/// the two sides' values are equal; OpenSubdiv's face-varying shapes
/// import with theirs.
#[test]
fn texture_coordinates_are_read_per_corner_with_their_seams() {
    let info = |text: &str| {
        let m = obj::parse(Path::new("two.obj"), text).unwrap();
        let uvs = m.uvs.clone().expect("texture coordinates");
        (m.cage.unwrap().uv.unwrap(), uvs)
    };
    let (whole, uvs) = info(&two_quads(false));
    assert_eq!(
        (whole.values, whole.seam_edges, whole.seam_vertices),
        (8, 0, 0)
    );
    assert_eq!(uvs.faces, vec![vec![0, 1, 2, 3], vec![1, 4, 5, 2]]);
    assert_eq!(uvs.values[4], [1.0, 0.0]);
    let (cut, uvs) = info(&two_quads(true));
    assert_eq!((cut.values, cut.seam_edges, cut.seam_vertices), (8, 1, 2));
    assert_eq!(uvs.faces[1], vec![6, 4, 5, 7]);
    assert!(obj::parse(Path::new("quad.obj"), QUAD)
        .unwrap()
        .uvs
        .is_none());

    // catmark_fvar_bound0: a 4×4 grid whose third row of faces takes new
    // `vt`s along the row of vertices 11..15 (4 edges), and whose last
    // face gives vertex 23 a value of its own (edge 18–23): 5 seam edges
    // through 6 vertices, as read off its `f` lines by hand.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/osd-fvar");
    let expected = [
        ("catmark_fvar_bound0", Some((5, 6))),
        ("catmark_fvar_bound1", None),
        ("catmark_fvar_bound2", None),
        ("catmark_fvar_bound3", None),
        ("catmark_fvar_bound4", None),
        ("catmark_fvar_project0", Some((0, 0))),
    ];
    for (name, seams) in expected {
        let path = dir.join(format!("{name}.obj"));
        let text = std::fs::read_to_string(&path).unwrap();
        let vt = text.lines().filter(|l| l.starts_with("vt ")).count();
        let faces = text.lines().filter(|l| l.starts_with("f ")).count();
        let m = obj::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let uv = m.cage.as_ref().unwrap().uv.expect(name);
        let uvs = m.uvs.as_ref().expect(name);
        assert_eq!((uv.values, uvs.faces.len()), (vt, faces), "{name}");
        assert!(uvs.faces.iter().flatten().all(|&t| t < vt), "{name}");
        match seams {
            Some(s) => assert_eq!((uv.seam_edges, uv.seam_vertices), s, "{name}"),
            // The seam shapes: each cuts its layout somewhere.
            None => assert!(uv.seam_edges > 0, "{name}: no seam"),
        }
    }
}
