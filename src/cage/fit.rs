//! Patches fitted to the limit surface where one patch per face cannot
//! follow OpenSubdiv's rules: next to semi-sharp creases and corners of
//! sharpness s below [`FIT_STEPS`] (sharp for s steps, then smooth: the
//! surface rounds the feature off within about 2^−s of a face, where the
//! converter's sharp rules leave a sharp crease), and where sharper creases
//! end or meet (there the sharp rules make a dart or a corner that the
//! surface is not).
//!
//! The surface there is first made exact by refining the cage until every
//! such feature has run out (`refine.rs`, ⌈s⌉ steps; [`END_STEPS`] at the
//! ends of sharper creases) and converting it
//! (`acc.rs`): the fine patches.
//! Then each such face gets the one bicubic patch that best matches the
//! fine patches in least squares, at the same parameters:
//!
//! - corner points stay the conversion's: limit positions (`limit.rs`
//!   refines the one-ring of a semi-sharp vertex or a dart to its limit);
//! - an edge's two inner points are the cubic with those ends that best
//!   matches the fine surface along the edge, when every face on the edge
//!   is fitted or a hole (else the conversion's are kept). Each is computed
//!   once, from the edge's first face with a patch, rounded once and copied
//!   into every patch on the edge: neighbours share their boundary bit for
//!   bit, as everywhere (DESIGN invariant 4);
//! - the four inner points best match the fine surface over the face, the
//!   boundary held.
//!
//! With isolation, the same fit is made for the patches of the irregular
//! ring at the last level ([`RING_STEPS`] finer), where the converter's
//! patch matches the surface's shape but not its parameters.
//!
//! This is an approximation with a documented bound, not the limit
//! surface: a feature narrower than a face cannot be drawn by one cubic
//! across it (tests/osd_reference.rs measures it); `isolate` makes it
//! exact.

use std::path::Path;
use std::sync::OnceLock;

use glam::{DVec3, Vec3};

use super::acc::{self, Conversion};
use super::mesh::{Cage, Topology};
use super::refine::StepTopologies;
use super::sharpness;
use crate::input::SceneError;

/// The most refinement steps the fine surface takes (each quarters the
/// faces: 256 fine patches per face at 4).
pub const FIT_STEPS: u32 = 4;

/// The most refinement steps the fine surface takes for the end of a
/// crease of sharpness [`FIT_STEPS`] or more. Measured on the OpenSubdiv
/// shapes: 3 brings `catmark_hole_test2` to 9.0e-4 (2 steps: 1.35e-3; 4:
/// 9.0e-4 and `catmark_chaikin1` 4.6e-3 to 2.8e-3) and adds 0.9 s to the
/// import of the car with its 24 crease ends of sharpness 6 (4 steps:
/// 9 s; 2: 0.3 s).
pub const END_STEPS: u32 = 3;

/// Refinement steps the fine surface takes beyond the last isolation
/// level for the irregular ring's patches (`isolate.rs`). Measured on the
/// `iso_*` cases at `isolate = 4`, parametric deviation: 2 steps bring the
/// cube from 2.8e-4 to 7.1e-5, pole64 from 5.3e-3 to 1.1e-3 and
/// xord_interior from 2.9e-3 to 2.5e-4; 3 steps 6.4e-5, 7.3e-4, 2.2e-4, at
/// four times the fine patches.
pub const RING_STEPS: u32 = 2;

/// The topologies of the fine surface's refinement ([`apply`]), kept for
/// the next conversion of the same faces (see [`StepTopologies`]).
#[derive(Default)]
pub struct FitTopologies {
    /// The fitted faces and their neighbours, and their topology before
    /// refinement.
    ring: OnceLock<(Vec<usize>, Topology)>,
    steps: StepTopologies,
}

/// Samples per patch side for the fits.
const SAMPLES: usize = 8;

/// What to fit and how finely: the patches [`wanted`] selects next to
/// semi-sharp features, and with isolation (`ring`) the irregular ring's
/// patches at the last level, whose converted patch matches the surface's
/// shape but not its parameters. Returns the selection and the refinement
/// steps the fine surface takes: [`steps`], at least [`RING_STEPS`] for
/// the ring; 0 when nothing is fitted.
pub fn plan(cage: &Cage, topo: &Topology, conv: &Conversion, ring: bool) -> (Vec<bool>, u32) {
    let ends: Vec<bool> = (0..cage.positions.len())
        .map(|v| feature_end(cage, topo, v))
        .collect();
    let mut steps = steps(cage, topo, &ends);
    let mut want = if steps > 0 {
        wanted(cage, topo, conv, &ends)
    } else {
        vec![false; conv.faces.len()]
    };
    if ring && conv.rules.iter().any(|r| !r.exact()) {
        for (w, r) in want.iter_mut().zip(&conv.rules) {
            *w |= !r.exact();
        }
        steps = steps.max(RING_STEPS);
    }
    (want, steps)
}

/// The sharpness of every edge at `v` (0 for smooth ones).
fn edge_sharpnesses<'a>(
    cage: &'a Cage,
    topo: &'a Topology,
    v: usize,
) -> impl Iterator<Item = f64> + 'a {
    topo.vertex_edges[v].iter().map(move |&e| {
        let (a, b) = topo.edges[e].ends;
        cage.edge_sharpness(a, b)
    })
}

/// Which patches of `conv` (of `cage`, adjacency `topo`) to fit: those
/// with a corner at a semi-sharp feature of sharpness below [`FIT_STEPS`],
/// or where a sharper one ends or meets others (`ends`, per vertex:
/// [`feature_end`]). Along a sharper crease the surface rounds the crease
/// off within about 2^−FIT_STEPS of a face and the converter's sharp rules
/// are left; where such a crease ends, its sharp conversion is a dart or
/// corner that the limit surface is not (4.1e-2 of the model at a crease
/// of sharpness 7.5 ending inside `catmark_hole_test2`, 9.0e-4 fitted).
/// Darts of infinitely sharp creases are not fitted: tried on the
/// OpenSubdiv shapes, it moved their largest deviation by at most a fifth
/// (the dart's own corner, exact since `limit.rs`, and its
/// parameterisation dominate), at ten times the import time of the car.
fn wanted(cage: &Cage, topo: &Topology, conv: &Conversion, ends: &[bool]) -> Vec<bool> {
    let soft = |s: f64| sharpness::is_semi_sharp(s) && s < f64::from(FIT_STEPS);
    let near = |v: usize| {
        soft(cage.vertex_sharpness(v)) || ends[v] || edge_sharpnesses(cage, topo, v).any(soft)
    };
    conv.faces
        .iter()
        .map(|&f| cage.faces[f].iter().any(|&v| near(v)))
        .collect()
}

/// Whether `v` ends or joins semi-sharp creases: a semi-sharp corner, a
/// semi-sharp edge with no other sharp edge at `v` (a crease ending inside
/// the surface: a dart while it is sharp), or three or more sharp edges of
/// which two are semi-sharp (creases meeting). Left out, measured on the
/// OpenSubdiv shapes: a semi-sharp crease meeting the boundary or an
/// infinitely sharp crease, and a change of sharpness along a crease; fitting
/// those too made `catmark_single_crease` worse (1.0e-3 to 1.5e-3) and
/// improved none.
fn feature_end(cage: &Cage, topo: &Topology, v: usize) -> bool {
    if sharpness::is_semi_sharp(cage.vertex_sharpness(v)) {
        return true;
    }
    let (mut sharp, mut semi) = (0, 0);
    for s in edge_sharpnesses(cage, topo, v).filter(|&s| s > 0.0) {
        sharp += 1;
        semi += usize::from(sharpness::is_semi_sharp(s));
    }
    (semi == 1 && sharp == 1) || (semi >= 2 && sharp >= 3)
}

/// Refinement steps the fine surface takes: until every semi-sharp
/// feature [`wanted`] fits has run out, at most [`FIT_STEPS`] (at most
/// [`END_STEPS`] for the ends of sharper creases, `ends` per vertex).
fn steps(cage: &Cage, topo: &Topology, ends: &[bool]) -> u32 {
    let semi = |s: &f64| sharpness::is_semi_sharp(*s);
    let soft = cage
        .edge_sharpness
        .values()
        .chain(cage.vertex_sharpness.values())
        .copied()
        .filter(|&s| semi(&s) && s < f64::from(FIT_STEPS));
    let ends = (0..cage.positions.len())
        .filter(|&v| ends[v])
        .flat_map(|v| edge_sharpnesses(cage, topo, v).chain([cage.vertex_sharpness(v)]))
        .filter(semi);
    let soft = soft.fold(0.0f64, f64::max).ceil() as u32;
    let ends = ends.fold(0.0f64, f64::max).ceil() as u32;
    soft.max(ends.min(END_STEPS)).min(FIT_STEPS)
}

/// Where a fine face lies in a coarse face: (coarse face, its corner (0,0),
/// its u and v directions), in the coarse face's parameters.
type Square = (usize, [f64; 2], [f64; 2], [f64; 2]);

/// The fine surface over each face of the coarse cage.
struct Fine {
    patches: Vec<[DVec3; 16]>,
    /// Per coarse face: (corner (0,0) of its square, side, fine patch).
    squares: Vec<Vec<([f64; 2], f64, usize)>>,
}

fn bern(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
}

fn eval(p: &[DVec3; 16], u: f64, v: f64) -> DVec3 {
    let (bu, bv) = (bern(u), bern(v));
    let mut s = DVec3::ZERO;
    for j in 0..4 {
        for i in 0..4 {
            s += p[4 * j + i] * (bu[i] * bv[j]);
        }
    }
    s
}

impl Fine {
    /// The faces `want` of `cage` and every face sharing a vertex with one
    /// (all their limit surface depends on: Catmull–Clark maps a face's
    /// one-ring to its sub-faces' one-rings) refined `steps` times and
    /// converted; each fine face remembers the square of the coarse face it
    /// covers. Fine faces of the ring are wrong near its outer border and
    /// are never sampled.
    fn new(
        cage: &Cage,
        topo: &Topology,
        want: &[usize],
        steps: u32,
        topos: &FitTopologies,
        path: &Path,
    ) -> Result<Self, SceneError> {
        let mut faces: Vec<usize> = want.to_vec();
        let mut taken = vec![false; cage.faces.len()];
        for &f in want {
            taken[f] = true;
        }
        for &f in want {
            for &v in &cage.faces[f] {
                for fan in &topo.fans[v] {
                    for &(g, _) in &fan.corners {
                        if !taken[g] {
                            taken[g] = true;
                            faces.push(g);
                        }
                    }
                }
            }
        }
        let (mut fine, _) = cage.extract(&faces);
        // Holes still give the fine surface its shape; every face converts.
        fine.holes.clear();
        let (ring, ring_topo) = match topos.ring.get() {
            Some(known) => known,
            None => {
                let t = Topology::build(&fine, path)?;
                topos.ring.get_or_init(|| (faces.clone(), t))
            }
        };
        // What is fitted follows from the tags and the topology alone.
        assert_eq!(ring, &faces, "FitTopologies reused for other faces");
        // Per fine face: (coarse face, corner (0,0) of its square, side),
        // the square's u and v along the fine face's own.
        let mut at: Vec<Square> = faces
            .iter()
            .map(|&f| (f, [0.0, 0.0], [1.0, 0.0], [0.0, 1.0]))
            .collect();
        let (fine, fine_topo) = topos.steps.refine(fine, ring_topo, steps, path, |subs| {
            at = subs
                .iter()
                .map(|s| {
                    let (f, o, du, dv) = at[s.face];
                    let q = super::refine::sub_quad_uv(s.corner);
                    let map = |p: [f32; 2]| {
                        let (a, b) = (f64::from(p[0]), f64::from(p[1]));
                        [o[0] + a * du[0] + b * dv[0], o[1] + a * du[1] + b * dv[1]]
                    };
                    let (c0, c1, c3) = (map(q[0]), map(q[1]), map(q[3]));
                    (
                        f,
                        c0,
                        [c1[0] - c0[0], c1[1] - c0[1]],
                        [c3[0] - c0[0], c3[1] - c0[1]],
                    )
                })
                .collect();
        })?;
        let conv = acc::convert_with(&fine, fine_topo, path, false)?;
        let mut squares = vec![Vec::new(); cage.faces.len()];
        let mut patches = Vec::with_capacity(conv.patches.len());
        for (p, &f) in conv.faces.iter().enumerate() {
            let (coarse, o, du, dv) = at[f];
            // Store the patch turned so that its u and v run along the
            // coarse face's: then the square is axis aligned from `lo`.
            let pts = conv.patches[p].pts.map(|q| q.as_dvec3());
            let side = (du[0].abs() + du[1].abs()).max(dv[0].abs() + dv[1].abs());
            let lo = [
                o[0].min(o[0] + du[0] + dv[0]),
                o[1].min(o[1] + du[1] + dv[1]),
            ];
            let aligned = align(&pts, du, dv);
            squares[coarse].push((lo, side, patches.len()));
            patches.push(aligned);
        }
        Ok(Fine { patches, squares })
    }

    /// The fine surface at (u, v) of coarse face `f`.
    fn at(&self, f: usize, u: f64, v: f64) -> Option<DVec3> {
        let eps = 1e-12;
        self.squares[f]
            .iter()
            .find(|(lo, side, _)| {
                u >= lo[0] - eps
                    && u <= lo[0] + side + eps
                    && v >= lo[1] - eps
                    && v <= lo[1] + side + eps
            })
            .map(|&(lo, side, p)| {
                let s = ((u - lo[0]) / side).clamp(0.0, 1.0);
                let t = ((v - lo[1]) / side).clamp(0.0, 1.0);
                eval(&self.patches[p], s, t)
            })
    }
}

/// The control points of a patch whose (u, v) axes map to the directions
/// `du`, `dv` of its square, reordered so that u and v run along +x and +y
/// of the square (a flip or a swap of the parameter axes).
fn align(p: &[DVec3; 16], du: [f64; 2], dv: [f64; 2]) -> [DVec3; 16] {
    // Which source index gives target (i, j).
    let swap = du[0] == 0.0;
    let (ax, ay) = if swap { (dv, du) } else { (du, dv) };
    let flip_i = ax[0] < 0.0;
    let flip_j = ay[1] < 0.0;
    std::array::from_fn(|n| {
        let (i, j) = (n % 4, n / 4);
        let (si, sj) = (
            if flip_i { 3 - i } else { i },
            if flip_j { 3 - j } else { j },
        );
        // Target (i along +x, j along +y): source u is x unless swapped.
        let (u, v) = if swap { (sj, si) } else { (si, sj) };
        p[4 * v + u]
    })
}

/// Rounds once to f32; +0.0 replaces -0.0.
fn round(p: DVec3) -> Vec3 {
    Vec3::new(p.x as f32, p.y as f32, p.z as f32) + Vec3::ZERO
}

/// Fits the patches of `conv` that `fit` marks (see the module doc); the
/// conversion's corners and edge points are updated too, for the tangent
/// patches. `cage` and `topo` are the cage `conv` converted; `topos`
/// keeps the fine surface's topologies for the next call on the same faces.
pub fn apply(
    cage: &Cage,
    topo: &Topology,
    conv: &mut Conversion,
    fit: &[bool],
    steps: u32,
    topos: &FitTopologies,
    path: &Path,
) -> Result<(), SceneError> {
    if !fit.iter().any(|&f| f) {
        return Ok(());
    }
    let patch_of = conv.patch_of_face();
    let want: Vec<usize> = conv
        .faces
        .iter()
        .zip(fit)
        .filter(|(_, &w)| w)
        .map(|(&f, _)| f)
        .collect();
    let fine = Fine::new(cage, topo, &want, steps, topos, path)?;
    // A hole has no patch to meet, so it does not hold a point back.
    let fitted_face = |f: usize| patch_of.get(&f).is_none_or(|&p| fit[p]);
    // Corners stay: the conversion's are the limit positions already.
    // Edges: where every face on the edge is fitted; from the first.
    for e in &topo.edges {
        if !e.uses.iter().all(|&(f, _)| fitted_face(f)) {
            continue;
        }
        let Some(&(f, k)) = e.uses.iter().find(|&&(f, _)| patch_of.contains_key(&f)) else {
            continue;
        };
        let face = &cage.faces[f];
        let (a, b) = (face[k], face[(k + 1) % 4]);
        let ends = [conv.corner[a].as_dvec3(), conv.corner[b].as_dvec3()];
        let samples: Vec<(f64, DVec3)> = (1..SAMPLES)
            .filter_map(|j| {
                let t = j as f64 / SAMPLES as f64;
                let (u, v) = edge_uv(k, t);
                fine.at(f, u, v).map(|x| (t, x))
            })
            .collect();
        let [p1, p2] = fit_curve(ends, &samples);
        conv.edge_point.insert((a, b), round(p1));
        conv.edge_point.insert((b, a), round(p2));
    }
    for (p, &f) in conv.faces.clone().iter().enumerate() {
        let face = &cage.faces[f];
        let mut pts = conv.patches[p].pts;
        let e = |a: usize, b: usize| conv.edge_point[&(a, b)];
        let c = |v: usize| conv.corner[v];
        let [v0, v1, v2, v3] = [face[0], face[1], face[2], face[3]];
        for (slot, value) in [
            (0, c(v0)),
            (1, e(v0, v1)),
            (2, e(v1, v0)),
            (3, c(v1)),
            (4, e(v0, v3)),
            (7, e(v1, v2)),
            (8, e(v3, v0)),
            (11, e(v2, v1)),
            (12, c(v3)),
            (13, e(v3, v2)),
            (14, e(v2, v3)),
            (15, c(v2)),
        ] {
            pts[slot] = value;
        }
        if fit[p] {
            let inner = fit_inner(&pts.map(|q| q.as_dvec3()), &|u, v| fine.at(f, u, v));
            for (slot, q) in [5, 6, 9, 10].into_iter().zip(inner) {
                pts[slot] = round(q);
            }
        }
        conv.patches[p].pts = pts;
        conv.patches[p] = conv.patches[p].canonical_zeros();
    }
    Ok(())
}

/// Parameters of the point at `t` along edge `k` of a patch, from corner
/// k to corner k + 1 (`shading::edge_uv` in f64).
fn edge_uv(k: usize, t: f64) -> (f64, f64) {
    match k {
        0 => (t, 0.0),
        1 => (1.0, t),
        2 => (1.0 - t, 1.0),
        _ => (0.0, 1.0 - t),
    }
}

/// The two inner control points of the cubic from `ends[0]` to `ends[1]`
/// that best matches the samples (t, point) in least squares.
fn fit_curve(ends: [DVec3; 2], samples: &[(f64, DVec3)]) -> [DVec3; 2] {
    let (mut a11, mut a12, mut a22) = (0.0, 0.0, 0.0);
    let (mut r1, mut r2) = (DVec3::ZERO, DVec3::ZERO);
    for &(t, x) in samples {
        let b = bern(t);
        let rest = x - ends[0] * b[0] - ends[1] * b[3];
        a11 += b[1] * b[1];
        a12 += b[1] * b[2];
        a22 += b[2] * b[2];
        r1 += rest * b[1];
        r2 += rest * b[2];
    }
    let det = a11 * a22 - a12 * a12;
    if det.abs() < 1e-300 {
        // No samples: the straight thirds.
        return [
            ends[0] + (ends[1] - ends[0]) / 3.0,
            ends[1] + (ends[0] - ends[1]) / 3.0,
        ];
    }
    [(r1 * a22 - r2 * a12) / det, (r2 * a11 - r1 * a12) / det]
}

/// The four inner control points (5, 6, 9, 10) of the patch with the
/// boundary of `p` that best match `surface` over an interior grid.
fn fit_inner(p: &[DVec3; 16], surface: &dyn Fn(f64, f64) -> Option<DVec3>) -> [DVec3; 4] {
    const INNER: [usize; 4] = [5, 6, 9, 10];
    let mut m = [[0.0f64; 4]; 4];
    let mut r = [DVec3::ZERO; 4];
    for j in 1..SAMPLES {
        for i in 1..SAMPLES {
            let (u, v) = (i as f64 / SAMPLES as f64, j as f64 / SAMPLES as f64);
            let Some(x) = surface(u, v) else { continue };
            let (bu, bv) = (bern(u), bern(v));
            let w = |n: usize| bu[n % 4] * bv[n / 4];
            let mut rest = x;
            for (n, q) in p.iter().enumerate() {
                if !INNER.contains(&n) {
                    rest -= *q * w(n);
                }
            }
            for (a, &na) in INNER.iter().enumerate() {
                r[a] += rest * w(na);
                for (b, &nb) in INNER.iter().enumerate() {
                    m[a][b] += w(na) * w(nb);
                }
            }
        }
    }
    solve4(m, r).unwrap_or([p[5], p[6], p[9], p[10]])
}

/// Solves the 4×4 system `m x = r` (vector right-hand side) by Gaussian
/// elimination with partial pivoting; `None` when singular.
fn solve4(mut m: [[f64; 4]; 4], mut r: [DVec3; 4]) -> Option<[DVec3; 4]> {
    for c in 0..4 {
        let pivot = (c..4).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs()))?;
        if m[pivot][c].abs() < 1e-300 {
            return None;
        }
        m.swap(c, pivot);
        r.swap(c, pivot);
        let (top, below) = m.split_at_mut(c + 1);
        let pivot_row = top[c];
        for (i, row) in below.iter_mut().enumerate() {
            let f = row[c] / pivot_row[c];
            for (x, &y) in row.iter_mut().zip(&pivot_row).skip(c) {
                *x -= f * y;
            }
            let rc = r[c];
            r[c + 1 + i] -= rc * f;
        }
    }
    let mut x = [DVec3::ZERO; 4];
    for c in (0..4).rev() {
        let mut s = r[c];
        for k in c + 1..4 {
            s -= x[k] * m[c][k];
        }
        x[c] = s / m[c][c];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_reproduce_a_cubic() {
        let ctrl = [
            DVec3::ZERO,
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(2.0, -1.0, 1.0),
            DVec3::new(3.0, 0.0, 0.0),
        ];
        let curve = |t: f64| {
            let b = bern(t);
            (0..4).map(|i| ctrl[i] * b[i]).sum::<DVec3>()
        };
        let samples: Vec<(f64, DVec3)> = (1..8)
            .map(|j| (j as f64 / 8.0, curve(j as f64 / 8.0)))
            .collect();
        let [p1, p2] = fit_curve([ctrl[0], ctrl[3]], &samples);
        assert!((p1 - ctrl[1]).length() < 1e-12 && (p2 - ctrl[2]).length() < 1e-12);
        let patch: [DVec3; 16] = std::array::from_fn(|n| {
            let (i, j) = ((n % 4) as f64, (n / 4) as f64);
            DVec3::new(i, j, (i * 1.3).sin() * (j * 0.7).cos())
        });
        let inner = fit_inner(&patch, &|u, v| Some(eval(&patch, u, v)));
        for (k, n) in [5, 6, 9, 10].into_iter().enumerate() {
            assert!((inner[k] - patch[n]).length() < 1e-12);
        }
    }

    #[test]
    fn alignment_undoes_the_sub_quad_turns() {
        let patch: [DVec3; 16] =
            std::array::from_fn(|n| DVec3::new((n % 4) as f64, (n / 4) as f64, 0.0));
        // Sub-quad 2 runs u towards -x and v towards -y.
        let a = align(&patch, [-0.5, 0.0], [0.0, -0.5]);
        assert_eq!(a[0], patch[15]);
        // Sub-quad 1 runs u along +y and v along -x.
        let b = align(&patch, [0.0, 0.5], [-0.5, 0.0]);
        // Target (0, 0) is the square's (min x, min y): u = 0 (y min), v = 1 (x min).
        assert_eq!(b[0], patch[12]);
    }
}
