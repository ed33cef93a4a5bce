//! Cages wound inside out: closed surfaces whose faces run clockwise seen
//! from outside (OpenSubdiv's `catmark_lefthanded`, a mirrored export).
//! Their limit surface is the same either way, but ∂S/∂u × ∂S/∂v points
//! inwards, so a one-sided renderer culls the outside and lights the
//! inside. Such a component is found by its signed volume and its patches
//! are turned the right way out by swapping u and v (`flip_patch`): the
//! control points are only reordered, so shared boundaries stay bit for bit
//! shared and the surface does not move.
//!
//! A component is a set of faces joined through manifold edges; it is
//! closed when every edge of its faces is manifold. Open components have no
//! inside and are left as they are (a scene marks such models `two_sided`);
//! so are closed ones whose volume is nearly zero (two sheets back to
//! back), where the sign says nothing.

use glam::DVec3;

use super::mesh::{Cage, Topology};
use crate::patch::bezier::BezierPatch;

/// Closed components enclosing less than this times the cube of their
/// bounding box's diagonal are left alone: the sign of a flat volume is
/// noise.
const FLAT_VOLUME: f64 = 1e-6;

/// What [`inside_out`] found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Orientation {
    /// Components joined through manifold edges.
    pub components: usize,
    /// Of those, closed ones.
    pub closed: usize,
    /// Of those, wound inside out (negative volume).
    pub inside_out: usize,
    /// Per face: it lies in an inside-out component.
    pub flip: Vec<bool>,
}

/// Finds the closed components of `cage` wound inside out.
pub fn inside_out(cage: &Cage, topo: &Topology) -> Orientation {
    let n = cage.faces.len();
    let mut component = vec![usize::MAX; n];
    let mut out = Orientation {
        flip: vec![false; n],
        ..Orientation::default()
    };
    for seed in 0..n {
        if component[seed] != usize::MAX {
            continue;
        }
        let id = out.components;
        out.components += 1;
        let mut faces = vec![seed];
        component[seed] = id;
        let mut closed = true;
        let mut at = 0;
        while at < faces.len() {
            let f = faces[at];
            at += 1;
            for &e in &topo.face_edges[f] {
                let edge = &topo.edges[e];
                if !edge.is_manifold() {
                    closed = false;
                    continue;
                }
                for &(g, _) in &edge.uses {
                    if component[g] == usize::MAX {
                        component[g] = id;
                        faces.push(g);
                    }
                }
            }
        }
        if !closed {
            continue;
        }
        out.closed += 1;
        if signed_volume(cage, &faces) < 0.0 {
            out.inside_out += 1;
            for &f in &faces {
                out.flip[f] = true;
            }
        }
    }
    out
}

/// The volume the faces enclose (positive when they run counter-clockwise
/// seen from outside), or 0 when it is too flat to say.
fn signed_volume(cage: &Cage, faces: &[usize]) -> f64 {
    let p = &cage.positions;
    let (mut lo, mut hi) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
    let mut sum = DVec3::ZERO;
    let mut count = 0.0;
    for &f in faces {
        for &v in &cage.faces[f] {
            lo = lo.min(p[v]);
            hi = hi.max(p[v]);
            sum += p[v];
            count += 1.0;
        }
    }
    let o = sum / count;
    let mut volume = 0.0;
    for &f in faces {
        let face = &cage.faces[f];
        let c = face.iter().map(|&v| p[v] - o).sum::<DVec3>() / face.len() as f64;
        for k in 0..face.len() {
            let (a, b) = (p[face[k]] - o, p[face[(k + 1) % face.len()]] - o);
            volume += a.cross(b).dot(c);
        }
    }
    volume /= 6.0;
    if volume.abs() <= FLAT_VOLUME * (hi - lo).length().powi(3) {
        0.0
    } else {
        volume
    }
}

/// The patch with u and v swapped: the same surface, the normal reversed.
pub fn flip_patch(p: &BezierPatch) -> BezierPatch {
    p.reoriented(true, false, false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn cube() -> Cage {
        crate::cage::mesh::unit_cube()
    }

    #[test]
    fn finds_the_cube_wound_inside_out() {
        let c = cube();
        let topo = Topology::build(&c, Path::new("cube")).unwrap();
        let o = inside_out(&c, &topo);
        assert_eq!((o.components, o.closed, o.inside_out), (1, 1, 0));
        assert!(signed_volume(&c, &[0, 1, 2, 3, 4, 5]) > 0.99);
        let mut c = cube();
        for f in &mut c.faces {
            f.reverse();
        }
        let topo = Topology::build(&c, Path::new("cube")).unwrap();
        let o = inside_out(&c, &topo);
        assert_eq!((o.components, o.closed, o.inside_out), (1, 1, 1));
        assert!(o.flip.iter().all(|&f| f));
        // An open box has no inside.
        c.faces.pop();
        c.face_lines.pop();
        let topo = Topology::build(&c, Path::new("box")).unwrap();
        let o = inside_out(&c, &topo);
        assert_eq!((o.components, o.closed, o.inside_out), (1, 0, 0));
    }
}
