//! Stencil tables: a converted cage as a fixed linear map of its vertices.
//!
//! For a fixed topology and tag set, the conversion of a cage to Bézier
//! patches (`refine.rs`, `acc.rs`, `limit.rs`, `fit.rs`) is linear in the
//! cage's vertex positions: every rule is a weighted sum whose weights
//! follow from valences, sharpness and sample parameters, never from where
//! the vertices are. So each control point is a fixed combination of cage
//! vertices, and an animated cage (a deformer, an OBJ sequence) can be
//! converted every frame by evaluating those combinations, on the GPU
//! (`glsl/anim_*.comp`) and on the CPU (this module) in the same f32
//! operations.
//!
//! # How the combinations are found
//!
//! By *probing* the conversion, not by writing its rules a second time: the
//! conversion is run on cages whose vertices are unit vectors in one
//! coordinate or zero, and each output then reads off the weight of the
//! vertex that lit it. Vertices far enough apart to share no output are lit
//! in the same run (a greedy colouring of the cage, three colours per run,
//! one per coordinate), so a cage takes a few tens of runs, not one per
//! vertex. This follows whatever the conversion computes, now and after it
//! changes, and needs nothing of it but linearity, which is checked: an
//! output lit where no vertex of that colour may reach it, or a table that
//! does not reproduce the conversion of the cage as loaded (within f32
//! rounding), widens the assumed reach and probes again, and fails the
//! import with a sentence past that. Anything that depends on positions is
//! decided once, from the cage as loaded: which closed parts are inside out
//! (`orient.rs`) and the shading construction's fits (`tangent.rs`).
//! Making the conversion generic over its point type would have found the
//! same weights in one run, at the price of rewriting every rule's code
//! around a second number type.
//!
//! # The tables
//!
//! - **Point rows**: one per distinct control point. A point that lies on a
//!   patch boundary is computed once by the conversion and copied into
//!   every patch on it (DESIGN invariant 4), so its probed combination is
//!   one and the same, and it gets one row, evaluated once per frame and
//!   read by every patch that uses it: neighbours get the same bits in
//!   every frame by construction. Rows are kept in the *reference form*
//!   x_r + Σₖ wₖ·(xₖ − x_r), x_r the vertex of the largest weight (the
//!   weights sum to 1): a point that is a vertex copies it exactly, and the
//!   rounding follows the size of the neighbourhood, not the distance from
//!   the origin.
//! - **Shading rows**: the 24 tangent vectors of each patch as combinations
//!   of point rows (`tangent::recipe`), Σₖ cₖ·(xₖ − x_r) (the coefficients
//!   sum to 0).
//!
//! Evaluation order, the contract with `glsl/common/anim.glsl`: per row,
//! an accumulator starts at +0 and adds wₖ·(xₖ − x_r) term by term in
//! stored order, per coordinate (one subtraction, one multiplication, one
//! addition, no fused multiply-add); a point row then adds x_r. Weights are
//! f32.

use std::collections::HashMap;

use glam::Vec3;

use crate::patch::bezier::BezierPatch;
use crate::patch::shading::ShadingPatch;

/// Rows of combinations in the reference form, compressed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// Per row, its first term; one more entry for the end.
    pub starts: Vec<u32>,
    /// Per row, the input it is relative to.
    pub refs: Vec<u32>,
    /// Per term, its input.
    pub index: Vec<u32>,
    /// Per term, its weight.
    pub weight: Vec<f32>,
}

/// Bytes of one term (input, weight) and of one row (start, reference) on
/// the GPU.
pub const TERM_BYTES: usize = 8;
/// See [`TERM_BYTES`].
pub const ROW_BYTES: usize = 8;

impl Table {
    /// Rows.
    pub fn rows(&self) -> usize {
        self.refs.len()
    }

    /// Terms of all rows.
    pub fn terms(&self) -> usize {
        self.index.len()
    }

    /// Bytes on the GPU.
    pub fn bytes(&self) -> usize {
        self.rows() * ROW_BYTES + self.terms() * TERM_BYTES
    }

    pub(super) fn push(&mut self, reference: u32, terms: &[(u32, f32)]) -> u32 {
        if self.starts.is_empty() {
            self.starts.push(0);
        }
        self.refs.push(reference);
        for &(i, w) in terms {
            self.index.push(i);
            self.weight.push(w);
        }
        self.starts.push(self.index.len() as u32);
        self.refs.len() as u32 - 1
    }

    /// Row `r`: its reference and terms.
    pub fn row(&self, r: usize) -> (u32, impl Iterator<Item = (u32, f32)> + '_) {
        let (a, b) = (self.starts[r] as usize, self.starts[r + 1] as usize);
        (
            self.refs[r],
            self.index[a..b]
                .iter()
                .copied()
                .zip(self.weight[a..b].iter().copied()),
        )
    }

    /// Σ wₖ·(xₖ − x_r) of row `r`, in the GPU's order.
    fn sum(&self, r: usize, x: &[Vec3]) -> (Vec3, Vec3) {
        let (reference, terms) = self.row(r);
        let base = x[reference as usize];
        let (mut ax, mut ay, mut az) = (0.0f32, 0.0f32, 0.0f32);
        for (i, w) in terms {
            let p = x[i as usize];
            ax += (p.x - base.x) * w;
            ay += (p.y - base.y) * w;
            az += (p.z - base.z) * w;
        }
        (base, Vec3::new(ax, ay, az))
    }

    /// Every row as a point: x_r + Σ wₖ·(xₖ − x_r).
    pub fn points(&self, x: &[Vec3]) -> Vec<Vec3> {
        (0..self.rows())
            .map(|r| {
                let (b, a) = self.sum(r, x);
                Vec3::new(b.x + a.x, b.y + a.y, b.z + a.z)
            })
            .collect()
    }

    /// Every row as a vector: Σ cₖ·(xₖ − x_r).
    pub fn vectors(&self, x: &[Vec3]) -> Vec<Vec3> {
        (0..self.rows()).map(|r| self.sum(r, x).1).collect()
    }

    /// Appends `other`, its inputs renamed by `input`.
    fn append(&mut self, other: &Table, input: &dyn Fn(u32) -> u32) {
        for r in 0..other.rows() {
            let (reference, terms) = other.row(r);
            let terms: Vec<(u32, f32)> = terms.map(|(i, w)| (input(i), w)).collect();
            self.push(input(reference), &terms);
        }
    }
}

/// The stencils of one converted cage: its patches and shading patches as
/// functions of its vertices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CageStencils {
    /// Cage vertices (the inputs), in the cage's order.
    pub vertices: usize,
    /// Point rows over cage vertices.
    pub points: Table,
    /// Per patch, the point row of each control point.
    pub patch_rows: Vec<[u32; 16]>,
    /// 24 rows per patch, in patch order (`ShadingPatch`'s ∂u then ∂v),
    /// over point rows.
    pub shading: Table,
}

impl CageStencils {
    /// Patches.
    pub fn patches(&self) -> usize {
        self.patch_rows.len()
    }

    /// Bytes on the GPU: both tables and the patches' row indices.
    pub fn bytes(&self) -> usize {
        self.points.bytes() + self.shading.bytes() + self.patch_rows.len() * 16 * 4
    }

    /// The patches and shading patches of the cage posed at `cage`.
    pub fn evaluate(&self, cage: &[Vec3]) -> (Vec<BezierPatch>, Vec<ShadingPatch>) {
        let points = self.points.points(cage);
        let vectors = self.shading.vectors(&points);
        let patches = self
            .patch_rows
            .iter()
            .map(|rows| BezierPatch {
                pts: rows.map(|r| points[r as usize]),
            })
            .collect();
        let shading = vectors
            .chunks_exact(24)
            .map(|v| ShadingPatch {
                du: std::array::from_fn(|n| v[n]),
                dv: std::array::from_fn(|n| v[12 + n]),
            })
            .collect();
        (patches, shading)
    }

    /// The patches `flip` marks with u and v swapped (`orient::flip_patch`,
    /// and their shading patches `ShadingPatch::transposed`): their rows
    /// are reordered as those reorder the points.
    pub fn flip(&mut self, flip: &[bool]) {
        if !flip.iter().any(|&f| f) {
            return;
        }
        let tag = |k: usize| Vec3::new(k as f32, 0.0, 0.0);
        let points = super::orient::flip_patch(&BezierPatch {
            pts: std::array::from_fn(tag),
        })
        .pts
        .map(|q| q.x as usize);
        let shading = ShadingPatch {
            du: std::array::from_fn(tag),
            dv: std::array::from_fn(|n| tag(12 + n)),
        }
        .transposed();
        let vectors: Vec<usize> = shading
            .du
            .iter()
            .chain(&shading.dv)
            .map(|q| q.x as usize)
            .collect();
        let mut table = Table::default();
        for (p, rows) in self.patch_rows.iter_mut().enumerate() {
            let turned = flip.get(p).copied().unwrap_or(false);
            if turned {
                let old = *rows;
                *rows = points.map(|k| old[k]);
            }
            for (k, &turn) in vectors.iter().enumerate() {
                let from = if turned { turn } else { k };
                let (reference, terms) = self.shading.row(24 * p + from);
                let terms: Vec<(u32, f32)> = terms.collect();
                table.push(reference, &terms);
            }
        }
        self.shading = table;
    }

    /// Joins the stencils of the parts of a cage: `parts` holds each
    /// part's stencils and the cage vertex of each of its vertices;
    /// `order` lists the patches of the result as (part, patch).
    pub fn join(
        vertices: usize,
        parts: &[(CageStencils, Vec<usize>)],
        order: &[(usize, usize)],
    ) -> CageStencils {
        let mut out = CageStencils {
            vertices,
            ..Default::default()
        };
        let mut row_base = Vec::new();
        for (s, map) in parts {
            row_base.push(out.points.rows() as u32);
            out.points.append(&s.points, &|i| map[i as usize] as u32);
        }
        for &(part, p) in order {
            let s = &parts[part].0;
            let base = row_base[part];
            out.patch_rows.push(s.patch_rows[p].map(|r| r + base));
            for k in 0..24 {
                let (reference, terms) = s.shading.row(24 * p + k);
                let terms: Vec<(u32, f32)> = terms.map(|(i, w)| (i + base, w)).collect();
                out.shading.push(reference + base, &terms);
            }
        }
        out
    }
}

/// A cage model as animation needs it: its stencils, its vertices as
/// loaded (the rest pose), and how they come from the file (another frame
/// of an OBJ sequence must have the same faces).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CageModel {
    /// The stencils of its patches.
    pub stencils: CageStencils,
    /// The cage's vertices as loaded.
    pub rest: Vec<Vec3>,
    /// The file vertex (0-based `v` statement) of each cage vertex.
    pub file_vertex: Vec<usize>,
    /// The file's faces: the 0-based `v` statement of each corner of each
    /// `f` statement.
    pub file_faces: Vec<Vec<usize>>,
    /// The file's `v` statements.
    pub file_vertices: usize,
}

impl CageModel {
    /// A patch file's patches as a "cage" of their distinct control points
    /// (shared boundary points, found by their bits, are one vertex): every
    /// point row one vertex, the shading rows the patches' own derivative
    /// nets (`ShadingPatch::from_geometry`, to the bit). So patch models
    /// animate by moving their control points.
    pub fn for_patches(patches: &[BezierPatch]) -> Self {
        let mut index: HashMap<[u32; 3], u32> = HashMap::new();
        let mut rest = Vec::new();
        let mut stencils = CageStencils::default();
        for p in patches {
            let rows = p.pts.map(|q| {
                *index
                    .entry(q.to_array().map(f32::to_bits))
                    .or_insert_with(|| {
                        rest.push(q);
                        stencils.points.push(rest.len() as u32 - 1, &[])
                    })
            });
            stencils.patch_rows.push(rows);
            let diff = |a: usize, b: usize| -> (u32, Vec<(u32, f32)>) {
                let (ra, rb) = (rows[a], rows[b]);
                if ra == rb {
                    return (ra, Vec::new());
                }
                // The reference form's reference is the lower input of two
                // equal weights: 3·(a − b) is −3·(b − a) to the bit.
                if ra < rb {
                    (ra, vec![(rb, -3.0)])
                } else {
                    (rb, vec![(ra, 3.0)])
                }
            };
            for n in 0..12 {
                let (i, j) = (n % 3, n / 3);
                let (r, t) = diff(4 * j + i + 1, 4 * j + i);
                stencils.shading.push(r, &t);
            }
            for n in 0..12 {
                let (i, j) = (n % 4, n / 4);
                let (r, t) = diff(4 * (j + 1) + i, 4 * j + i);
                stencils.shading.push(r, &t);
            }
        }
        stencils.vertices = rest.len();
        CageModel {
            stencils,
            file_vertex: (0..rest.len()).collect(),
            file_vertices: rest.len(),
            rest,
            file_faces: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::probe::reference_form;

    #[test]
    fn rows_evaluate_in_the_reference_form() {
        let mut t = Table::default();
        t.push(1, &[(0, 0.25), (2, 0.25)]);
        t.push(2, &[]);
        let x = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(3.0, 1.0, 0.0),
            Vec3::new(5.0, 2.0, 4.0),
        ];
        assert_eq!(t.points(&x), vec![Vec3::new(3.0, 1.0, 1.0), x[2]]);
        assert_eq!(t.vectors(&x)[0], Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(t.bytes(), 2 * ROW_BYTES + 2 * TERM_BYTES);
    }

    #[test]
    fn reference_is_the_largest_weight() {
        let (r, rest) = reference_form(&[(3, 0.25), (5, 0.5), (9, 0.25)], 1.0).unwrap();
        assert_eq!((r, rest), (5, vec![(3, 0.25), (9, 0.25)]));
        assert!(reference_form(&[(3, 0.5)], 1.0).is_none());
        assert!(reference_form(&[(3, 3.0), (4, -3.0)], 0.0).is_some());
    }
}
