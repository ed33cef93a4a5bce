//! A cage's texture coordinates as OBJ gives them: face-varying, each
//! corner of each face naming a `vt`, so a cage vertex has one value per
//! side of a UV seam (OpenSubdiv's face-varying channel; its topology is
//! the `vt` indices, not their values). The import reads, checks and
//! reports them; the UV patches and the texture path build on them.

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;

use super::acc;
use super::isolate;
use super::mesh::{Cage, Topology};
use super::origin::PatchOrigin;
use super::refine::QUAD_UV;
use super::scan::Scan;
use super::sharpness::{self, BoundaryRule};
use super::stencil::CageStencils;
use crate::input::SceneError;

/// The texture coordinates of a cage's faces.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceUvs {
    /// The `vt` values (u, v), in file order.
    pub values: Vec<[f32; 2]>,
    /// Per cage face, per corner (in the face's order): the index of its
    /// value in `values`.
    pub faces: Vec<Vec<usize>>,
}

/// What the import found of a cage's texture coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UvInfo {
    /// `vt` values.
    pub values: usize,
    /// Edges shared by faces that give their ends different `vt`s: the UV
    /// layout is cut there.
    pub seam_edges: usize,
    /// Cage vertices with more than one `vt` among their faces' corners.
    pub seam_vertices: usize,
}

impl FaceUvs {
    /// The texture coordinates the scan read, for `cage`'s faces (the
    /// scan's `f` statements in order); `None` for a file without them,
    /// and, with a warning pushed to `warnings`, for one whose faces have
    /// them only in part (the model is imported without: a stated
    /// fallback, since a cage's shape does not depend on them).
    pub(super) fn from_scan(
        path: &Path,
        scan: &Scan,
        cage: &Cage,
        warnings: &mut Vec<String>,
    ) -> Result<Option<Self>, SceneError> {
        if let Some((line, why)) = &scan.uv_problem {
            warnings.push(format!(
                "texture coordinates ignored: line {line}: {why} (give every corner of every \
                 face a `vt`, as `v/vt`, or none)"
            ));
            return Ok(None);
        }
        if scan.uv_faces.iter().all(Option::is_none) {
            return Ok(None);
        }
        let faces: Vec<Vec<usize>> = scan.uv_faces.iter().flatten().cloned().collect();
        let same_faces = faces.len() == cage.faces.len()
            && faces
                .iter()
                .zip(&cage.faces)
                .all(|(t, f)| t.len() == f.len());
        if !same_faces {
            return Err(SceneError::invalid(
                path,
                "the OBJ reader's faces do not match the file's `f` lines, so their texture \
                 coordinates cannot be placed",
            ));
        }
        Ok(Some(Self {
            values: scan.uvs.clone(),
            faces,
        }))
    }

    /// Its seams in `cage` (whose faces these are).
    pub fn info(&self, cage: &Cage) -> UvInfo {
        // Per cage vertex, the distinct `vt`s its corners name.
        let mut at_vertex: HashMap<usize, Vec<usize>> = HashMap::new();
        // Per undirected edge, the `vt`s each face gives its (smaller,
        // larger) ends.
        let mut at_edge: HashMap<(usize, usize), Vec<(usize, usize)>> = HashMap::new();
        for (face, uvs) in cage.faces.iter().zip(&self.faces) {
            let n = face.len();
            for k in 0..n {
                let seen = at_vertex.entry(face[k]).or_default();
                if !seen.contains(&uvs[k]) {
                    seen.push(uvs[k]);
                }
                let (a, b) = (k, (k + 1) % n);
                let key = if face[a] < face[b] {
                    ((face[a], face[b]), (uvs[a], uvs[b]))
                } else {
                    ((face[b], face[a]), (uvs[b], uvs[a]))
                };
                at_edge.entry(key.0).or_default().push(key.1);
            }
        }
        UvInfo {
            values: self.values.len(),
            seam_edges: at_edge
                .values()
                .filter(|sides| sides.iter().any(|s| *s != sides[0]))
                .count(),
            seam_vertices: at_vertex.values().filter(|uvs| uvs.len() > 1).count(),
        }
    }
}

/// How texture coordinates are interpolated across the surface:
/// OpenSubdiv's `FVarLinearInterpolation`, the two rules built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FvarRule {
    /// `FVAR_LINEAR_CORNERS_ONLY` (OpenSubdiv's and USD's default): smooth
    /// like the positions, a UV seam a boundary whose corners stay put.
    #[default]
    CornersOnly,
    /// `FVAR_LINEAR_ALL`: bilinear across each face.
    All,
}

impl FvarRule {
    /// Its name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            FvarRule::CornersOnly => "corners-only",
            FvarRule::All => "all",
        }
    }
}

impl std::str::FromStr for FvarRule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "corners-only" => Ok(FvarRule::CornersOnly),
            "all" => Ok(FvarRule::All),
            _ => Err(format!(
                "unknown face-varying rule {s:?}: expected corners-only or all"
            )),
        }
    }
}

impl<'de> serde::Deserialize<'de> for FvarRule {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

/// The (u, v) of a patch's 16 control points, `[4 * v + u]` as
/// [`BezierPatch::pts`](crate::patch::bezier::BezierPatch).
pub type UvPatch = [[f32; 2]; 16];

/// Each patch's texture coordinates, and how each was made.
#[derive(Clone, Debug, PartialEq)]
pub struct UvPatches {
    /// The rule they follow.
    pub rule: FvarRule,
    /// One per patch, in patch order.
    pub patches: Vec<UvPatch>,
    /// Per patch: exactly the rule's limit (`false`: near a seam under
    /// `corners-only`, where the bilinear patch stands in, or where the
    /// position patch itself approximates the limit surface).
    pub exact: Vec<bool>,
}

/// What [`uv_patches`] needs of a converted cage.
pub struct Converted<'a> {
    /// The cage, its sharpness resolved.
    pub cage: &'a Cage,
    /// Where each patch came from.
    pub origins: &'a [PatchOrigin],
    /// The patches as combinations of the cage's vertices.
    pub stencils: &'a CageStencils,
    /// The cage's boundary rule.
    pub boundary: BoundaryRule,
    /// The model's `isolate`: the UV cage is refined as the cage is.
    pub isolate: u32,
}

/// The UV patches of `cage`'s patches under `rule`.
///
/// `all`: bilinear across each face (each patch lies in one face, or one
/// sub-face of an n-gon, whose corners' UVs are those of the face's `vt`s,
/// its edges' midpoints and its centroid), exact. `corners-only`, in turn:
/// where none of the cage vertices a patch's control points combine is a
/// seam vertex, the face-varying topology there is the vertices' and
/// OpenSubdiv applies the vertices' rules, so the position stencils
/// applied to the vertices' UVs give the UV patch (exact wherever the
/// positions are); a quad whose corners no other face shares is an
/// island, bilinear, exact; the rest take their region of the UV cage's
/// conversion ([`uv_cage`]), exact where its patch is. Where that cannot
/// be had (a boundary rule other than edge-and-corner, a face that is not
/// a quad) the bilinear patch stands in, counted as not exact.
pub fn uv_patches(uvs: &FaceUvs, cage: &Converted<'_>, rule: FvarRule) -> UvPatches {
    let faces = &cage.cage.faces;
    let bilinear: Vec<UvPatch> = cage
        .origins
        .iter()
        .map(|o| bilinear_patch(uvs, faces, o))
        .collect();
    let mut exact = vec![rule == FvarRule::All; bilinear.len()];
    let mut patches = bilinear;
    if rule == FvarRule::CornersOnly && cage.boundary == BoundaryRule::EdgeAndCorner {
        let (vertex_uv, single) = vertex_uvs(uvs, faces, cage.cage.positions.len());
        let points = cage.stencils.points.points(&vertex_uv);
        let clean: Vec<bool> = (0..cage.stencils.points.rows())
            .map(|r| {
                let (reference, mut terms) = cage.stencils.points.row(r);
                single[reference as usize] && terms.all(|(i, _)| single[i as usize])
            })
            .collect();
        for (p, rows) in cage.stencils.patch_rows.iter().enumerate() {
            if rows.iter().all(|&r| clean[r as usize]) {
                patches[p] = rows.map(|r| [points[r as usize].x, points[r as usize].y]);
                // As exact as the position patch the stencils make.
                exact[p] = cage.origins[p].rule.exact();
            }
        }
    }
    if rule == FvarRule::CornersOnly {
        // A quad that shares no corner's value with another face is a UV
        // island of one face: every edge a seam, every corner pinned, so
        // its limit is the bilinear map (per-face layouts, ptex-like).
        let alone = lone_quads(uvs, faces);
        for (p, o) in cage.origins.iter().enumerate() {
            if !exact[p] && alone[o.face] {
                exact[p] = true;
            }
        }
    }
    let seams_left = exact.iter().any(|e| !e);
    if rule == FvarRule::CornersOnly && cage.boundary == BoundaryRule::EdgeAndCorner && seams_left {
        // Next to a seam: the UV cage's own conversion, each patch the
        // region of its face's UV patch it covers.
        if let Some(pieces) = uv_face_pieces(uvs, cage.cage, cage.isolate) {
            for (p, o) in cage.origins.iter().enumerate() {
                if exact[p] {
                    continue;
                }
                let r = region(o);
                let sub = (cage.cage.faces[o.face].len() != 4).then_some(o.sub);
                let found = pieces[o.face]
                    .iter()
                    .find(|q| q.sub == sub && covers(&q.corners, &r));
                if let Some(piece) = found {
                    patches[p] = restrict(&piece.patch, r.map(|x| local(&piece.corners, x)));
                    exact[p] = piece.exact;
                }
            }
        }
    }
    UvPatches {
        rule,
        patches,
        exact,
    }
}

/// Per face: a quad none of whose corners shares its (vertex, `vt`) pair
/// with another face.
fn lone_quads(uvs: &FaceUvs, faces: &[Vec<usize>]) -> Vec<bool> {
    let mut users: HashMap<(usize, usize), u32> = HashMap::new();
    for (face, corners) in faces.iter().zip(&uvs.faces) {
        for (&v, &t) in face.iter().zip(corners) {
            *users.entry((v, t)).or_default() += 1;
        }
    }
    faces
        .iter()
        .zip(&uvs.faces)
        .map(|(face, corners)| {
            face.len() == 4 && face.iter().zip(corners).all(|(&v, &t)| users[&(v, t)] == 1)
        })
        .collect()
}

/// Each cage vertex's UV as a point (u, v, 0), and whether it has exactly
/// one (a vertex on a seam has several; one in no face none).
fn vertex_uvs(uvs: &FaceUvs, faces: &[Vec<usize>], vertices: usize) -> (Vec<Vec3>, Vec<bool>) {
    let mut index: Vec<Option<usize>> = vec![None; vertices];
    let mut single = vec![false; vertices];
    let mut seam = vec![false; vertices];
    for (face, corners) in faces.iter().zip(&uvs.faces) {
        for (&v, &t) in face.iter().zip(corners) {
            match index[v] {
                None => {
                    index[v] = Some(t);
                    single[v] = true;
                }
                Some(seen) if seen != t => seam[v] = true,
                Some(_) => {}
            }
        }
    }
    let points = index
        .iter()
        .map(|t| {
            t.map_or(Vec3::ZERO, |t| {
                Vec3::new(uvs.values[t][0], uvs.values[t][1], 0.0)
            })
        })
        .collect();
    let single = single.iter().zip(&seam).map(|(&s, &x)| s && !x).collect();
    (points, single)
}

/// The corners of the patch in its (sub-)face; a turned whole sub-face has
/// its u and v swapped.
fn region(o: &PatchOrigin) -> [[f32; 2]; 4] {
    o.corners_uv.unwrap_or(if o.turned {
        [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]
    } else {
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    })
}

/// The bilinear UV patch of the (sub-)face region `o` covers.
fn bilinear_patch(uvs: &FaceUvs, faces: &[Vec<usize>], o: &PatchOrigin) -> UvPatch {
    let t: Vec<[f32; 2]> = uvs.faces[o.face].iter().map(|&i| uvs.values[i]).collect();
    let n = t.len();
    // The (sub-)face's corners at (0,0), (1,0), (1,1), (0,1).
    let square = if faces[o.face].len() == 4 {
        [t[0], t[1], t[2], t[3]]
    } else {
        let k = o.sub;
        let mid = |a: [f32; 2], b: [f32; 2]| [(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5];
        let sum = t
            .iter()
            .fold([0.0f32; 2], |s, c| [s[0] + c[0], s[1] + c[1]]);
        let centre = [sum[0] / n as f32, sum[1] / n as f32];
        [
            t[k],
            mid(t[k], t[(k + 1) % n]),
            centre,
            mid(t[(k + n - 1) % n], t[k]),
        ]
    };
    let c = region(o).map(|[s, u]| bilinear(square, s, u));
    std::array::from_fn(|k| bilinear(c, (k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0))
}

/// The point at (s, t) of the bilinear map whose corners (0,0), (1,0),
/// (1,1), (0,1) lie at `c`.
fn bilinear(c: [[f32; 2]; 4], s: f32, t: f32) -> [f32; 2] {
    let lerp =
        |a: [f32; 2], b: [f32; 2], x: f32| [a[0] + (b[0] - a[0]) * x, a[1] + (b[1] - a[1]) * x];
    lerp(lerp(c[0], c[1], s), lerp(c[3], c[2], s), t)
}

/// The face-varying channel as a cage of its own: one vertex per (cage
/// vertex, `vt`) pair (OpenSubdiv's sibling values: a `vt` index shared by
/// faces at different vertices is not one vertex), placed at its (u, v);
/// the faces, holes, sharpness and scheme of `cage` (sharpness resolved,
/// so the surface's boundary and corners come along). Its own boundary,
/// the UV seams, then takes the edge-and-corner rule, which is
/// `corners-only`'s.
fn uv_cage(uvs: &FaceUvs, cage: &Cage) -> Cage {
    let mut id: HashMap<(usize, usize), usize> = HashMap::new();
    let mut out = Cage {
        scheme: cage.scheme,
        holes: cage.holes.clone(),
        face_lines: cage.face_lines.clone(),
        ..Cage::default()
    };
    let mut vertex_of = Vec::new();
    for (face, corners) in cage.faces.iter().zip(&uvs.faces) {
        let ids: Vec<usize> = face
            .iter()
            .zip(corners)
            .map(|(&v, &t)| {
                *id.entry((v, t)).or_insert_with(|| {
                    let [u, w] = uvs.values[t];
                    out.positions
                        .push(glam::DVec3::new(f64::from(u), f64::from(w), 0.0));
                    vertex_of.push(v);
                    out.positions.len() - 1
                })
            })
            .collect();
        let n = face.len();
        for k in 0..n {
            let (a, b) = (face[k], face[(k + 1) % n]);
            if let Some(&s) = cage.edge_sharpness.get(&(a.min(b), a.max(b))) {
                let (x, y) = (ids[k], ids[(k + 1) % n]);
                out.edge_sharpness.insert((x.min(y), x.max(y)), s);
            }
        }
        out.faces.push(ids);
    }
    for (i, &v) in vertex_of.iter().enumerate() {
        if let Some(&s) = cage.vertex_sharpness.get(&v) {
            out.vertex_sharpness.insert(i, s);
        }
    }
    out
}

/// A patch of the UV cage's conversion: where it lies in its cage face,
/// its points, and whether it is exactly the face-varying limit.
struct Piece {
    /// For a face that is not a quad, the sub-face the piece lies in
    /// (its corners are in that sub-face's parameters).
    sub: Option<usize>,
    corners: [[f32; 2]; 4],
    patch: UvPatch,
    exact: bool,
}

/// Per cage face, the pieces of the UV cage's conversion that lie in it:
/// with `isolate` > 0 the patches of its refinement (where the UV cage
/// needs it), for a cage with faces that are not quads those of its one
/// refinement step, then for a cage of quads its unrefined patch; `None`
/// where the converter refuses the UV cage's topology, in which case the
/// callers keep their stand-ins.
fn uv_face_pieces(uvs: &FaceUvs, cage: &Cage, isolate: u32) -> Option<Vec<Vec<Piece>>> {
    let path = Path::new("texture coordinates");
    let mut uvc = uv_cage(uvs, cage);
    let topo = Topology::build(&uvc, path).ok()?;
    sharpness::resolve(&mut uvc, &topo, BoundaryRule::EdgeAndCorner);
    let mut out: Vec<Vec<Piece>> = (0..cage.faces.len()).map(|_| Vec::new()).collect();
    let points = |p: &crate::patch::bezier::BezierPatch| p.pts.map(|q| [q.x, q.y]);
    let quads = cage.faces.iter().all(|f| f.len() == 4);
    if isolate > 0 || !quads {
        // The refinement's pieces (a cage with faces that are not quads
        // is refined once, as the surface is): a patch takes the first
        // piece that covers it.
        let conv = isolate::convert(&uvc, &topo, isolate, &[], path).ok()?;
        for (patch, o) in conv.patches.iter().zip(&conv.origins) {
            out[o.face].push(Piece {
                sub: (cage.faces[o.face].len() != 4).then_some(o.sub),
                corners: region(o),
                patch: points(patch),
                exact: o.rule.exact(),
            });
        }
    }
    if quads {
        // Then each face's unrefined patch, for a patch the refinement's
        // pieces are smaller than (its part of the cage was not refined,
        // the UV cage's was).
        let conv = acc::convert(&uvc, &topo, path).ok()?;
        for ((patch, &face), rule) in conv.patches.iter().zip(&conv.faces).zip(&conv.rules) {
            out[face].push(Piece {
                sub: None,
                corners: QUAD_UV,
                patch: points(patch),
                exact: rule.exact(),
            });
        }
    }
    Some(out)
}

/// Per cage face: its texture coordinates would be approximated without
/// refinement (`corners-only` under edge-and-corner, next to a seam, where
/// the UV cage's own patch of the face is not exact: an extraordinary
/// vertex of the UV layout). Isolation refines the parts holding such
/// faces, so their UV patches come out exact as their positions do.
/// Empty where nothing is known to need it.
pub fn inexact_faces(
    uvs: &FaceUvs,
    cage: &Cage,
    rule: FvarRule,
    boundary: BoundaryRule,
) -> Vec<bool> {
    if rule != FvarRule::CornersOnly || boundary != BoundaryRule::EdgeAndCorner {
        return Vec::new();
    }
    let Some(pieces) = uv_face_pieces(uvs, cage, 0) else {
        return Vec::new();
    };
    let alone = lone_quads(uvs, &cage.faces);
    pieces
        .iter()
        .zip(alone)
        .map(|(p, alone)| !alone && p.iter().any(|q| !q.exact))
        .collect()
}

/// Whether the rectangle with corners `outer` holds the one with corners
/// `inner` (both in one face's parameters).
fn covers(outer: &[[f32; 2]; 4], inner: &[[f32; 2]; 4]) -> bool {
    let range = |c: &[[f32; 2]; 4], a: usize| {
        c.iter().fold((f32::MAX, f32::MIN), |(lo, hi), p| {
            (lo.min(p[a]), hi.max(p[a]))
        })
    };
    (0..2).all(|a| {
        let ((olo, ohi), (ilo, ihi)) = (range(outer, a), range(inner, a));
        olo <= ilo && ihi <= ohi
    })
}

/// Face point `x` in the parameters of the rectangle whose corners (0,0),
/// (1,0), (1,1), (0,1) lie at `c` (axis-aligned, any orientation).
fn local(c: &[[f32; 2]; 4], x: [f32; 2]) -> [f32; 2] {
    let d = [x[0] - c[0][0], x[1] - c[0][1]];
    let along = |e: [f32; 2]| (d[0] * e[0] + d[1] * e[1]) / (e[0] * e[0] + e[1] * e[1]);
    [
        along([c[1][0] - c[0][0], c[1][1] - c[0][1]]),
        along([c[3][0] - c[0][0], c[3][1] - c[0][1]]),
    ]
}

/// `patch` restricted to the region of its parameter square whose corners
/// (0,0), (1,0), (1,1), (0,1) lie at `corners`: an axis-aligned rectangle
/// in any of the square's eight orientations (a sub-quad of a refined face
/// runs its u along the face's v, or backwards), by de Casteljau in f64.
/// The rectangle's box is cut out first (rows along the patch's u), then
/// the net is read in the region's orientation: a Bézier net under a
/// symmetry of the square is the same points, reordered.
fn restrict(patch: &UvPatch, corners: [[f32; 2]; 4]) -> UvPatch {
    let c = corners.map(|p| [f64::from(p[0]), f64::from(p[1])]);
    let range = |axis: usize| {
        c.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
            (lo.min(p[axis]), hi.max(p[axis]))
        })
    };
    let ((u0, u1), (v0, v1)) = (range(0), range(1));
    let net: Vec<[f64; 2]> = patch
        .iter()
        .map(|p| [f64::from(p[0]), f64::from(p[1])])
        .collect();
    // Rows (along u) restricted to [u0, u1], then columns to [v0, v1]:
    // boxed[j][i], i along u.
    let mut rows = [[[0.0f64; 2]; 4]; 4];
    for (j, row) in rows.iter_mut().enumerate() {
        *row = segment(
            [net[4 * j], net[4 * j + 1], net[4 * j + 2], net[4 * j + 3]],
            u0,
            u1,
        );
    }
    let mut boxed = [[[0.0f64; 2]; 4]; 4];
    for i in 0..4 {
        let col = segment(rows.map(|row| row[i]), v0, v1);
        for (j, p) in col.iter().enumerate() {
            boxed[j][i] = *p;
        }
    }
    // Output point (i, j) lies at c0 + i/3 (c1 - c0) + j/3 (c3 - c0):
    // the box's grid point there.
    let index = |x: f64, lo: f64, hi: f64| ((x - lo) / (hi - lo) * 3.0).round() as usize;
    std::array::from_fn(|k| {
        let (i, j) = ((k % 4) as f64 / 3.0, (k / 4) as f64 / 3.0);
        let at = |a: usize| c[0][a] + i * (c[1][a] - c[0][a]) + j * (c[3][a] - c[0][a]);
        let p = boxed[index(at(1), v0, v1)][index(at(0), u0, u1)];
        [p[0] as f32, p[1] as f32]
    })
}

/// The cubic `c` on [a, b] as a cubic on [0, 1] (de Casteljau: split at
/// b, then the left part at a / b).
fn segment(c: [[f64; 2]; 4], a: f64, b: f64) -> [[f64; 2]; 4] {
    let split = |c: [[f64; 2]; 4], t: f64| -> ([[f64; 2]; 4], [[f64; 2]; 4]) {
        let l = |p: [f64; 2], q: [f64; 2]| [p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t];
        let (a1, b1, c1) = (l(c[0], c[1]), l(c[1], c[2]), l(c[2], c[3]));
        let (a2, b2) = (l(a1, b1), l(b1, c1));
        let m = l(a2, b2);
        ([c[0], a1, a2, m], [m, b2, c1, c[3]])
    };
    let left = if b < 1.0 { split(c, b).0 } else { c };
    if a > 0.0 {
        split(left, a / b).1
    } else {
        left
    }
}
