//! A cage's texture coordinates as OBJ gives them: face-varying, each
//! corner of each face naming a `vt`, so a cage vertex has one value per
//! side of a UV seam (OpenSubdiv's face-varying channel; its topology is
//! the `vt` indices, not their values). The import reads, checks and
//! reports them; the UV patches and the texture path build on them.

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;

use super::mesh::Cage;
use super::origin::PatchOrigin;
use super::scan::Scan;
use super::sharpness::BoundaryRule;
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
    /// The cage's faces.
    pub faces: &'a [Vec<usize>],
    /// Its vertices.
    pub vertices: usize,
    /// Where each patch came from.
    pub origins: &'a [PatchOrigin],
    /// The patches as combinations of the cage's vertices.
    pub stencils: &'a CageStencils,
    /// The cage's boundary rule.
    pub boundary: BoundaryRule,
}

/// The UV patches of `cage`'s patches under `rule`.
///
/// `all`: bilinear across each face (each patch lies in one face, or one
/// sub-face of an n-gon, whose corners' UVs are those of the face's `vt`s,
/// its edges' midpoints and its centroid), exact. `corners-only`: where
/// none of the cage vertices a patch's control points combine is a seam
/// vertex, the face-varying topology there is the vertices' and OpenSubdiv
/// applies the vertices' rules, so the position stencils applied to the
/// vertices' UVs give the UV patch, exact wherever the positions are
/// (isolation included) and as close as they are elsewhere; a quad whose
/// corners no other face shares is an island, bilinear, exact; under
/// another boundary rule than edge-and-corner, and near a seam, the
/// bilinear patch stands in (not exact, counted).
pub fn uv_patches(uvs: &FaceUvs, cage: &Converted<'_>, rule: FvarRule) -> UvPatches {
    let bilinear: Vec<UvPatch> = cage
        .origins
        .iter()
        .map(|o| bilinear_patch(uvs, cage.faces, o))
        .collect();
    let mut exact = vec![rule == FvarRule::All; bilinear.len()];
    let mut patches = bilinear;
    if rule == FvarRule::CornersOnly && cage.boundary == BoundaryRule::EdgeAndCorner {
        let (vertex_uv, single) = vertex_uvs(uvs, cage.faces, cage.vertices);
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
        let alone = lone_quads(uvs, cage.faces);
        for (p, o) in cage.origins.iter().enumerate() {
            if !exact[p] && alone[o.face] {
                exact[p] = true;
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
    let at = |[s, u]: [f32; 2]| {
        let lerp =
            |a: [f32; 2], b: [f32; 2], x: f32| [a[0] + (b[0] - a[0]) * x, a[1] + (b[1] - a[1]) * x];
        lerp(
            lerp(square[0], square[1], s),
            lerp(square[3], square[2], s),
            u,
        )
    };
    // The patch's corners in the (sub-)face; a turned whole sub-face has
    // its u and v swapped.
    let corners = o.corners_uv.unwrap_or(if o.turned {
        [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]
    } else {
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    });
    let c = corners.map(at);
    std::array::from_fn(|k| {
        let (i, j) = ((k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0);
        let lerp =
            |a: [f32; 2], b: [f32; 2], x: f32| [a[0] + (b[0] - a[0]) * x, a[1] + (b[1] - a[1]) * x];
        lerp(lerp(c[0], c[1], i), lerp(c[3], c[2], i), j)
    })
}
