//! The limit surface of one model as one welded triangle mesh: every model
//! patch on a uniform grid, the vertices along shared patch edges merged, so
//! the mesh is closed wherever the model is (the input of the simplifier and
//! of every error measurement in [`super::error`]).

use std::collections::HashMap;

use glam::Vec3;

use crate::patch::bezier::BezierPatch;

/// A triangle mesh with a unit normal per vertex.
#[derive(Clone, Debug, Default)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per vertex, its unit normals: the limit surface's (∂u × ∂v) from
    /// each patch that meets there, those within [`SMOOTH_COS`] of each
    /// other averaged into one. A vertex on a crease has one per side; a
    /// triangle takes the one nearest its own normal ([`TriMesh::split`]),
    /// which then comes first (the one drawn), the other sides' after it.
    pub normals: Vec<Vec<Vec3>>,
    /// Per vertex: its texture coordinates, those of the patch it was
    /// first sampled from (continuous across patches where the model's UV
    /// layout is; across a UV seam a triangle blends the two sides').
    pub st: Vec<[f32; 2]>,
    /// Three indices per triangle, wound like ∂u × ∂v.
    pub indices: Vec<u32>,
}

impl TriMesh {
    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// Triangle `t`'s corners.
    pub fn triangle(&self, t: usize) -> [Vec3; 3] {
        let i = &self.indices[3 * t..3 * t + 3];
        [
            self.positions[i[0] as usize],
            self.positions[i[1] as usize],
            self.positions[i[2] as usize],
        ]
    }

    /// How many of this mesh's open edges ([`TriMesh::boundary_edges`])
    /// end at a point that is not on `source`'s own open boundary: 0 for a
    /// simplification of `source` that opened it nowhere (collapses keep
    /// the source's vertex positions, so a border can be compared by them).
    pub fn edges_opened_from(&self, source: &TriMesh) -> usize {
        let key = |m: &TriMesh, v: u32| m.positions[v as usize].to_array().map(f32::to_bits);
        let border: std::collections::HashSet<[u32; 3]> = source
            .boundary_edges()
            .iter()
            .flat_map(|&(a, b)| [key(source, a), key(source, b)])
            .collect();
        self.boundary_edges()
            .iter()
            .filter(|&&(a, b)| !border.contains(&key(self, a)) || !border.contains(&key(self, b)))
            .count()
    }

    /// The edges used by exactly one triangle, each as (lower, higher)
    /// vertex index, sorted: the mesh's open boundary. Vertices at the same
    /// position (a crease's split copies) count as one: the first.
    pub fn boundary_edges(&self) -> Vec<(u32, u32)> {
        let mut first: HashMap<[u32; 3], u32> = HashMap::new();
        let canon: Vec<u32> = (0..self.positions.len() as u32)
            .map(|v| {
                let key = self.positions[v as usize].to_array().map(f32::to_bits);
                *first.entry(key).or_insert(v)
            })
            .collect();
        let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
        for t in self.indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (canon[t[k] as usize], canon[t[(k + 1) % 3] as usize]);
                *uses.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let mut open: Vec<(u32, u32)> = uses
            .into_iter()
            .filter(|&(_, n)| n == 1)
            .map(|(e, _)| e)
            .collect();
        open.sort_unstable();
        open
    }
}

/// Merges points closer than `tol` into one vertex. Points are bucketed on
/// a grid of cell `tol`; a point looks in its cell and the 26 around it, so
/// two points within `tol` always meet whatever cell boundary lies between.
struct Welder {
    tol: f32,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl Welder {
    fn new(tol: f32) -> Self {
        Self {
            tol,
            cells: HashMap::new(),
        }
    }

    fn cell(&self, p: Vec3) -> [i64; 3] {
        let c = (p / self.tol).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    }

    /// The vertex at `p`: an existing one within `tol`, else a new one.
    fn vertex(&mut self, p: Vec3, n: Vec3, st: [f32; 2], mesh: &mut TriMesh) -> u32 {
        let c = self.cell(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                    let Some(list) = self.cells.get(&key) else {
                        continue;
                    };
                    for &v in list {
                        if mesh.positions[v as usize].distance(p) <= self.tol {
                            add_normal(&mut mesh.normals[v as usize], n);
                            return v;
                        }
                    }
                }
            }
        }
        let v = mesh.positions.len() as u32;
        mesh.positions.push(p);
        mesh.normals.push(vec![n]);
        mesh.st.push(st);
        self.cells.entry(c).or_default().push(v);
        v
    }
}

/// The patches on a grid of `n` × `n` cells each, welded (points within
/// 10⁻⁶ of the model's size merged), triangles that welding collapsed (at a
/// patch's degenerate corner) dropped. Each cell is cut along the diagonal
/// from (u, v) to (u + h, v + h). `st(k, u, v)`: the texture coordinates
/// of patch k at (u, v).
pub fn limit_mesh(
    patches: &[BezierPatch],
    n: usize,
    st: &dyn Fn(usize, f32, f32) -> [f32; 2],
) -> TriMesh {
    let mut mesh = TriMesh::default();
    let Some((lo, hi)) = BezierPatch::bounds(patches) else {
        return mesh;
    };
    let mut welder = Welder::new((hi - lo).length().max(1e-20) * 1e-6);
    let h = 1.0 / n as f32;
    let mut ids = vec![0u32; (n + 1) * (n + 1)];
    for (k, p) in patches.iter().enumerate() {
        for j in 0..=n {
            for i in 0..=n {
                // Exact 0 and 1 at the ends, so neighbours evaluate their
                // shared boundary curve at the same parameters.
                let (u, v) = (param(i, n, h), param(j, n, h));
                let normal = p.normal(u, v).normalize_or_zero();
                let st = st(k, u, v);
                ids[j * (n + 1) + i] = welder.vertex(p.eval(u, v), normal, st, &mut mesh);
            }
        }
        for j in 0..n {
            for i in 0..n {
                let a = ids[j * (n + 1) + i];
                let b = ids[j * (n + 1) + i + 1];
                let c = ids[(j + 1) * (n + 1) + i + 1];
                let d = ids[(j + 1) * (n + 1) + i];
                push_triangle(&mut mesh.indices, [a, b, c]);
                push_triangle(&mut mesh.indices, [a, c, d]);
            }
        }
    }
    for list in &mut mesh.normals {
        for n in list.iter_mut() {
            *n = n.normalize_or_zero();
        }
    }
    mesh
}

fn param(i: usize, n: usize, h: f32) -> f32 {
    if i == n {
        1.0
    } else {
        i as f32 * h
    }
}

/// Normals of patches meeting at a vertex closer than this cosine (about
/// 25°) are one smooth normal there; farther apart, a crease.
pub const SMOOTH_COS: f32 = 0.9;

/// Adds the unit normal `n` to the vertex normals `list`: to the one
/// within [`SMOOTH_COS`] of it (unnormalised sums), else as a new one.
fn add_normal(list: &mut Vec<Vec3>, n: Vec3) {
    match list
        .iter_mut()
        .find(|m| m.normalize_or_zero().dot(n) >= SMOOTH_COS)
    {
        Some(m) => *m += n,
        None => list.push(n),
    }
}

impl TriMesh {
    /// The triangles `indices` over this mesh's vertices as a mesh of their
    /// own: only the vertices they use, each once per normal its
    /// triangles take (each corner the vertex normal nearest the
    /// triangle's own), so a crease stays sharp however far the triangles
    /// around it were simplified.
    pub fn split(&self, indices: &[u32]) -> TriMesh {
        let mut out = TriMesh::default();
        let mut made: HashMap<(u32, usize), u32> = HashMap::new();
        for t in indices.chunks_exact(3) {
            let p: [Vec3; 3] = std::array::from_fn(|k| self.positions[t[k] as usize]);
            let face = (p[1] - p[0]).cross(p[2] - p[0]);
            for &i in t {
                let list = &self.normals[i as usize];
                let k = (0..list.len())
                    .max_by(|&a, &b| list[a].dot(face).total_cmp(&list[b].dot(face)))
                    .unwrap_or(0);
                let v = *made.entry((i, k)).or_insert_with(|| {
                    out.positions.push(self.positions[i as usize]);
                    // The chosen normal first (the one drawn), the other
                    // sides' after it: a crease vertex keeps more than one.
                    let mut normals = list.clone();
                    if normals.is_empty() {
                        normals.push(Vec3::Z);
                    }
                    let last = normals.len() - 1;
                    normals.swap(0, k.min(last));
                    out.normals.push(normals);
                    out.st.push(self.st[i as usize]);
                    out.positions.len() as u32 - 1
                });
                out.indices.push(v);
            }
        }
        out
    }
}

/// The texture coordinates of a model without a UV layout: the patch's
/// own (u, v), as the shaders' `surface_uv` gives them.
pub fn plain_uv(_: usize, u: f32, v: f32) -> [f32; 2] {
    [u, v]
}

/// Appends a triangle unless two of its corners are one vertex.
fn push_triangle(indices: &mut Vec<u32>, t: [u32; 3]) {
    if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
        indices.extend_from_slice(&t);
    }
}

/// Test shapes: the unit cube's faces as patches, pushed out towards a
/// sphere (curved, closed), each face's ∂u × ∂v outward.
#[cfg(test)]
pub(crate) mod shapes {
    use glam::Vec3;

    use crate::patch::bezier::BezierPatch;
    use crate::patch::fixtures;

    const FACES: [[Vec3; 3]; 6] = [
        [Vec3::ZERO, Vec3::Y, Vec3::X],
        [Vec3::Z, Vec3::X, Vec3::Y],
        [Vec3::ZERO, Vec3::Z, Vec3::Y],
        [Vec3::X, Vec3::Y, Vec3::Z],
        [Vec3::ZERO, Vec3::X, Vec3::Z],
        [Vec3::Y, Vec3::Z, Vec3::X],
    ];

    /// The unit cube's faces, each cut into `k` × `k` patches, each point
    /// bent by `bend`.
    pub fn cube_with(k: usize, bend: impl Fn(Vec3) -> Vec3) -> Vec<BezierPatch> {
        let mut out = Vec::new();
        let s = 1.0 / k as f32;
        for [o, a, b] in FACES {
            for j in 0..k {
                for i in 0..k {
                    out.push(fixtures::grid(|x, y| {
                        let (x, y) = ((i as f32 + x / 3.0) * s, (j as f32 + y / 3.0) * s);
                        bend(o + a * x + b * y)
                    }));
                }
            }
        }
        out
    }

    /// The cube's control points pushed onto the sphere around its centre,
    /// `k` × `k` patches a face.
    pub fn ball(k: usize) -> Vec<BezierPatch> {
        cube_with(k, |p| (p - Vec3::splat(0.5)).normalize() * 0.8)
    }

    /// A box with flat faces and narrow rounded edges (the control points
    /// pushed onto a superellipsoid of exponent 8), `k` × `k` patches a face.
    pub fn rounded_box(k: usize) -> Vec<BezierPatch> {
        cube_with(k, |p| {
            let q = p - Vec3::splat(0.5);
            let a = q.abs();
            let norm = (a.x.powi(8) + a.y.powi(8) + a.z.powi(8)).powf(0.125);
            q * (0.5 / norm.max(1e-12))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_model_welds_into_a_closed_mesh() {
        let mesh = limit_mesh(&shapes::ball(1), 4, &plain_uv);
        assert_eq!(mesh.triangles(), 6 * 4 * 4 * 2);
        assert_eq!(mesh.boundary_edges(), vec![]);
        // A cube's grid: 6 faces of 5 × 5 points, edges and corners shared.
        assert_eq!(mesh.positions.len(), 6 * 9 + 12 * 3 + 8);
    }

    #[test]
    fn an_open_model_keeps_its_boundary() {
        let mesh = limit_mesh(&shapes::ball(1)[..5], 4, &plain_uv);
        assert_eq!(mesh.boundary_edges().len(), 16);
    }
}
