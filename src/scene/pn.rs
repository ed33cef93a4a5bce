//! PN triangles (Vlachos et al. 2001; Schwarz and Stamminger 2009, §4):
//! triangle meshes read from OBJ files, drawn by `cudatess` as cubic Bézier
//! triangles with a quadratic normal field built from each triangle's
//! three vertex positions and normals.
//!
//! A mesh vertex is a (position, normal) pair: the file's `vn` where the
//! face gives one, else the area-weighted average of the face normals
//! around the position (one per position, so both triangles of an edge see
//! the same normal). Two triangle sides are one edge when their two end
//! vertices are bit-identical in position and normal: exactly then both
//! triangles build the same cubic boundary curve (see [`control_net`]) and
//! write the same points on it. Quads and n-gons are fanned from their
//! first vertex.
//!
//! [`control_net`] is the CPU twin of the conversion in
//! `glsl/cudatess/pn_factors.comp` (the tests compare the two).

use std::collections::HashMap;
use std::path::Path;

use glam::{DMat4, Vec3};

use crate::input::SceneError;

/// One triangle mesh, in object or (after [`PnMesh::transformed`]) world
/// space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PnMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, parallel to `positions`.
    pub normals: Vec<Vec3>,
    /// Counter-clockwise (seen from outside) vertex triples.
    pub triangles: Vec<[u32; 3]>,
}

/// Control net of one PN triangle: the cubic's 10 points and the quadratic
/// normal field's 6 coefficients.
///
/// Points: `b300, b030, b003` (the corners P0, P1, P2), then the edge
/// points `b210, b120` (edge 0: P0 → P1), `b021, b012` (edge 1: P1 → P2),
/// `b102, b201` (edge 2: P2 → P0), then the centre `b111`. Normals:
/// `n200, n020, n002, n110, n011, n101`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PnNet {
    /// The cubic's control points.
    pub b: [Vec3; 10],
    /// The normal field's coefficients.
    pub n: [Vec3; 6],
}

/// The edge point next to `p` on the edge towards `q`: `p`'s neighbour
/// projected into the tangent plane at `p` (Vlachos: b210 = (2 P1 + P2 −
/// w12 N1) / 3 with w12 = (P2 − P1)·N1). Computed from (p, q, n) alone and
/// in the same order as the shader, so both triangles of an edge get it.
pub fn edge_point(p: Vec3, q: Vec3, n: Vec3) -> Vec3 {
    let w = (q - p).dot(n);
    (p * 2.0 + q - n * w) / 3.0
}

/// The normal coefficient of the edge p → q (Vlachos: n110 = N1 + N2 −
/// v12 (P2 − P1), v12 = 2 (P2 − P1)·(N1 + N2) / |P2 − P1|², normalised).
pub fn edge_normal(p: Vec3, q: Vec3, np: Vec3, nq: Vec3) -> Vec3 {
    let d = q - p;
    let dd = d.dot(d);
    let v = if dd > 0.0 {
        2.0 * d.dot(np + nq) / dd
    } else {
        0.0
    };
    (np + nq - d * v).normalize_or_zero()
}

/// The control net of the triangle with positions `p` and normals `n`.
pub fn control_net(p: [Vec3; 3], n: [Vec3; 3]) -> PnNet {
    let e = [
        edge_point(p[0], p[1], n[0]),
        edge_point(p[1], p[0], n[1]),
        edge_point(p[1], p[2], n[1]),
        edge_point(p[2], p[1], n[2]),
        edge_point(p[2], p[0], n[2]),
        edge_point(p[0], p[2], n[0]),
    ];
    let big_e = (e[0] + e[1] + e[2] + e[3] + e[4] + e[5]) / 6.0;
    let v = (p[0] + p[1] + p[2]) / 3.0;
    let centre = big_e + (big_e - v) * 0.5;
    PnNet {
        b: [p[0], p[1], p[2], e[0], e[1], e[2], e[3], e[4], e[5], centre],
        n: [
            n[0],
            n[1],
            n[2],
            edge_normal(p[0], p[1], n[0], n[1]),
            edge_normal(p[1], p[2], n[1], n[2]),
            edge_normal(p[2], p[0], n[2], n[0]),
        ],
    }
}

impl PnNet {
    /// The cubic at barycentric (1 − u − v, u, v).
    pub fn eval(&self, u: f32, v: f32) -> Vec3 {
        let w = 1.0 - u - v;
        let b = &self.b;
        b[0] * (w * w * w)
            + b[1] * (u * u * u)
            + b[2] * (v * v * v)
            + (b[3] * (w * w * u) + b[4] * (w * u * u)) * 3.0
            + (b[5] * (u * u * v) + b[6] * (u * v * v)) * 3.0
            + (b[7] * (v * v * w) + b[8] * (v * w * w)) * 3.0
            + b[9] * (6.0 * w * u * v)
    }

    /// The normal field at (u, v), unnormalised (Vlachos's sum without
    /// binomial weights on the mixed terms).
    pub fn normal(&self, u: f32, v: f32) -> Vec3 {
        let w = 1.0 - u - v;
        let n = &self.n;
        n[0] * (w * w)
            + n[1] * (u * u)
            + n[2] * (v * v)
            + n[3] * (w * u)
            + n[4] * (u * v)
            + n[5] * (w * v)
    }
}

impl PnMesh {
    /// The mesh under the affine map `m` (positions in f64, rounded once;
    /// normals by the inverse transpose, normalised). A mirroring map
    /// reverses every triangle to keep them counter-clockwise from outside.
    pub fn transformed(&self, m: &DMat4) -> PnMesh {
        let normal_map = m.inverse().transpose();
        let mirror = m.determinant() < 0.0;
        PnMesh {
            positions: self
                .positions
                .iter()
                .map(|p| m.transform_point3(p.as_dvec3()).as_vec3())
                .collect(),
            normals: self
                .normals
                .iter()
                .map(|n| {
                    normal_map
                        .transform_vector3(n.as_dvec3())
                        .normalize_or_zero()
                        .as_vec3()
                })
                .collect(),
            triangles: self
                .triangles
                .iter()
                .map(|&[a, b, c]| if mirror { [a, c, b] } else { [a, b, c] })
                .collect(),
        }
    }

    /// The control net of triangle `t`.
    pub fn net(&self, t: usize) -> PnNet {
        let [a, b, c] = self.triangles[t].map(|i| i as usize);
        control_net(
            [self.positions[a], self.positions[b], self.positions[c]],
            [self.normals[a], self.normals[b], self.normals[c]],
        )
    }
}

/// Reads an OBJ file as a PN-triangle mesh.
pub fn read(path: &Path) -> Result<PnMesh, SceneError> {
    let text = crate::input::text::read_text(path)?;
    parse(path, &text)
}

/// A face corner: position index and, where given, normal index (0-based).
type Corner = (usize, Option<usize>);

/// Parses OBJ text (`v`, `vn`, `f`; texture coordinates, groups, materials
/// and smoothing statements are ignored); `path` only names the source in
/// errors, which give its line.
pub fn parse(path: &Path, text: &str) -> Result<PnMesh, SceneError> {
    let mut positions: Vec<Vec3> = Vec::new();
    let mut file_normals: Vec<Vec3> = Vec::new();
    let mut faces: Vec<(usize, Vec<Corner>)> = Vec::new();
    for (line_no, keyword, rest) in crate::input::text::statements(text) {
        let err = |msg: String| SceneError::at(path, line_no, msg);
        match keyword {
            "v" | "vn" => {
                let p = three_numbers(&rest).map_err(|m| err(format!("`{keyword}` {m}")))?;
                if keyword == "v" {
                    positions.push(p);
                } else if p.length_squared() > 0.0 {
                    file_normals.push(p.normalize());
                } else {
                    return Err(err("a normal (`vn`) of length 0".into()));
                }
            }
            "f" => {
                let corners = crate::cage::scan::face_corners(&rest, |r| {
                    corner(r, positions.len(), file_normals.len())
                })
                .map_err(err)?;
                faces.push((line_no, corners));
            }
            "l" | "p" => {
                return Err(err(format!(
                    "`{keyword}` statements are not supported: PN triangles need faces"
                )))
            }
            _ => {}
        }
    }
    if faces.is_empty() {
        return Err(SceneError::invalid(
            path,
            "no faces (`f` lines): nothing to draw as PN triangles",
        ));
    }
    build(path, &positions, &file_normals, &faces)
}

/// `x y z` (a `w` or colour after them is ignored), all finite.
fn three_numbers(words: &[&str]) -> Result<Vec3, String> {
    if words.len() < 3 {
        return Err(format!("needs 3 numbers, found {}", words.len()));
    }
    let mut xyz = [0f32; 3];
    for (k, w) in words[..3].iter().enumerate() {
        xyz[k] = w
            .parse::<f32>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("coordinate `{w}` is not a finite number"))?;
    }
    Ok(Vec3::from_array(xyz))
}

/// One `v`, `v/vt`, `v//vn` or `v/vt/vn` reference; negative indices count
/// back from the last element read so far.
fn corner(word: &str, positions: usize, normals: usize) -> Result<Corner, String> {
    let parts: Vec<&str> = word.split('/').collect();
    let index = |s: &str, have: usize, what: &str| -> Result<usize, String> {
        let k: i64 = s
            .parse()
            .map_err(|_| format!("face vertex `{word}`: `{s}` is not an index"))?;
        let at = if k > 0 { k - 1 } else { have as i64 + k };
        if k == 0 || at < 0 || at >= have as i64 {
            return Err(format!(
                "face vertex `{word}` refers to {what} {k}, but {have} are defined before this line"
            ));
        }
        Ok(at as usize)
    };
    let v = index(parts[0], positions, "position")?;
    let n = match parts.get(2) {
        Some(s) if !s.is_empty() => Some(index(s, normals, "normal")?),
        _ => None,
    };
    Ok((v, n))
}

/// The mesh: vertices are the distinct (position, normal) pairs the faces
/// use; positions without a file normal get the area-weighted average of
/// their faces' normals.
fn build(
    path: &Path,
    positions: &[Vec3],
    file_normals: &[Vec3],
    faces: &[(usize, Vec<Corner>)],
) -> Result<PnMesh, SceneError> {
    let mut triangles_at: Vec<(usize, [Corner; 3])> = Vec::new();
    for (line, f) in faces {
        for k in 1..f.len() - 1 {
            triangles_at.push((*line, [f[0], f[k], f[k + 1]]));
        }
    }
    let mut averaged = vec![Vec3::ZERO; positions.len()];
    for (line, t) in &triangles_at {
        let [a, b, c] = t.map(|(v, _)| positions[v]);
        let n = (b - a).cross(c - a);
        if !n.is_finite() || n.length_squared() <= 0.0 {
            return Err(SceneError::at(
                path,
                *line,
                "a degenerate triangle (its corners are collinear or repeated)",
            ));
        }
        for (v, _) in t {
            averaged[*v] += n;
        }
    }
    let mut mesh = PnMesh::default();
    let mut index: HashMap<(usize, Option<usize>), u32> = HashMap::new();
    for (_, t) in &triangles_at {
        let tri = t.map(|(v, n)| {
            *index.entry((v, n)).or_insert_with(|| {
                mesh.positions.push(positions[v]);
                mesh.normals.push(match n {
                    Some(k) => file_normals[k],
                    None => averaged[v].normalize_or_zero(),
                });
                mesh.positions.len() as u32 - 1
            })
        });
        mesh.triangles.push(tri);
    }
    Ok(mesh)
}

/// The PN triangles of a whole scene: every instance's mesh in world space,
/// concatenated, with the edge of each triangle side.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PnScene {
    /// World-space positions of every instance's vertices.
    pub positions: Vec<Vec3>,
    /// Unit normals, parallel to `positions`.
    pub normals: Vec<Vec3>,
    /// Vertex indices into `positions` (scene-wide).
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: the model index `<< PATCH_MODEL_SHIFT` and
    /// `PATCH_TWO_SIDED`, like a patch's flags.
    pub flags: Vec<u32>,
    /// Per triangle, the edge ids of its sides 0: P0 → P1, 1: P1 → P2,
    /// 2: P2 → P0 (numbered 0..edges).
    pub edge_ids: Vec<[u32; 3]>,
    /// Distinct edges.
    pub edges: u32,
}

impl PnScene {
    /// Adds `mesh` (already in world space) with the flags word `flags`.
    pub fn push(&mut self, mesh: &PnMesh, flags: u32) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&mesh.positions);
        self.normals.extend_from_slice(&mesh.normals);
        for t in &mesh.triangles {
            self.triangles.push(t.map(|i| i + base));
            self.flags.push(flags);
        }
    }

    /// Numbers the edges: sides whose end vertices have the same position
    /// and normal bits, in either order, are one edge (ids in order of first
    /// appearance).
    pub fn number_edges(&mut self) {
        let key_of = |v: u32| -> [u32; 6] {
            let (p, n) = (self.positions[v as usize], self.normals[v as usize]);
            [p.x, p.y, p.z, n.x, n.y, n.z].map(f32::to_bits)
        };
        let mut index: HashMap<([u32; 6], [u32; 6]), u32> = HashMap::new();
        let mut ids = Vec::with_capacity(self.triangles.len());
        for t in &self.triangles {
            let mut sides = [0u32; 3];
            for (k, id) in sides.iter_mut().enumerate() {
                let (a, b) = (key_of(t[k]), key_of(t[(k + 1) % 3]));
                let next = index.len() as u32;
                *id = *index
                    .entry(if a <= b { (a, b) } else { (b, a) })
                    .or_insert(next);
            }
            ids.push(sides);
        }
        self.edge_ids = ids;
        self.edges = index.len() as u32;
    }

    /// The control net of triangle `t`.
    pub fn net(&self, t: usize) -> PnNet {
        let [a, b, c] = self.triangles[t].map(|i| i as usize);
        control_net(
            [self.positions[a], self.positions[b], self.positions[c]],
            [self.normals[a], self.normals[b], self.normals[c]],
        )
    }

    /// Triangles in the scene.
    pub fn count(&self) -> u32 {
        self.triangles.len() as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_str(text: &str) -> Result<PnMesh, SceneError> {
        parse(Path::new("m.obj"), text)
    }

    #[test]
    fn quads_are_fanned_and_normals_averaged_per_position() {
        let m = parse_str("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 -1\nf 1 2 3 4\nf 2 1 5\n")
            .unwrap();
        assert_eq!(m.triangles.len(), 3);
        assert_eq!(m.positions.len(), 5);
        // Vertex 1 (index 0) is on the quad (normal +z) and the wall (+y
        // side, normal -y): the average leans between them.
        let n = m.normals[0];
        assert!(n.z > 0.0 && n.y < 0.0, "{n}");
        assert!((n.length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn bad_input_names_the_line() {
        let e = parse_str("v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap_err();
        assert!(e.to_string().contains("m.obj:3"), "{e}");
        assert!(e.to_string().contains("position 3"), "{e}");
        let e = parse_str("v 0 0 0\nv 1 0 x\n").unwrap_err();
        assert!(e.to_string().contains("m.obj:2"), "{e}");
        let e = parse_str("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap_err();
        assert!(e.to_string().contains("degenerate"), "{e}");
        assert!(parse_str("v 0 0 0\n").is_err());
    }

    #[test]
    fn shared_sides_are_one_edge() {
        let m = parse_str("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n").unwrap();
        let mut s = PnScene::default();
        s.push(&m, 0);
        s.number_edges();
        assert_eq!(s.edges, 5);
        assert_eq!(s.edge_ids[0][2], s.edge_ids[1][0]);
    }

    #[test]
    fn a_flat_triangle_stays_flat() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let net = control_net(p, [Vec3::Z; 3]);
        for (u, v) in [(0.2, 0.3), (0.5, 0.5), (0.0, 0.7)] {
            let q = net.eval(u, v);
            assert!((q - Vec3::new(u, v, 0.0)).length() < 1e-6, "{q}");
        }
    }

    #[test]
    fn control_points_follow_vlachos() {
        // Off the origin, so a wrong weight on P0 shows.
        let o = Vec3::new(0.5, -1.0, 2.0);
        let p = [o, o + Vec3::X, o + Vec3::Y];
        let n0 = Vec3::new(-0.6, 0.0, 0.8);
        let net = control_net(p, [n0, Vec3::Z, Vec3::Z]);
        // b210 = (2 P0 + P1 - w01 N0) / 3, w01 = (P1 - P0).N0 = -0.6.
        let b210 = o + Vec3::new(1.0 - 0.36, 0.0, 0.48) / 3.0;
        assert!((net.b[3] - b210).length() < 1e-6, "{}", net.b[3]);
        // Every edge point lies in its corner's tangent plane.
        for (k, corner, normal) in [(3, 0, n0), (4, 1, Vec3::Z), (8, 0, n0), (7, 2, Vec3::Z)] {
            assert!((net.b[k] - p[corner]).dot(normal).abs() < 1e-6, "point {k}");
        }
        // b111 = E + (E - V) / 2.
        let e: Vec3 = net.b[3..9].iter().sum::<Vec3>() / 6.0;
        let v = (p[0] + p[1] + p[2]) / 3.0;
        assert!((net.b[9] - (e + (e - v) * 0.5)).length() < 1e-6);
        // n110 = N0 + N1 - v01 (P1 - P0), v01 = 2 (P1 - P0).(N0 + N1) / 1.
        let n110 = (n0 + Vec3::Z - Vec3::X * (2.0 * -0.6)).normalize();
        assert!((net.n[3] - n110).length() < 1e-6, "{}", net.n[3]);
        // Corners and corner normals are interpolated.
        assert_eq!(net.eval(0.0, 0.0), p[0]);
        assert!((net.eval(1.0, 0.0) - p[1]).length() < 1e-6);
        assert!((net.normal(0.0, 0.0) - n0).length() < 1e-6);
    }

    #[test]
    fn mirroring_reverses_triangles() {
        let m = parse_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let t = m.transformed(&DMat4::from_scale(glam::DVec3::new(-1.0, 1.0, 1.0)));
        assert_eq!(t.triangles[0], [0, 2, 1]);
        assert!((t.normals[0] - Vec3::Z).length() < 1e-6);
    }
}
