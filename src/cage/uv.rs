//! A cage's texture coordinates as OBJ gives them: face-varying, each
//! corner of each face naming a `vt`, so a cage vertex has one value per
//! side of a UV seam (OpenSubdiv's face-varying channel; its topology is
//! the `vt` indices, not their values). The import reads, checks and
//! reports them; the UV patches and the texture path build on them.

use std::collections::HashMap;
use std::path::Path;

use super::mesh::Cage;
use super::scan::Scan;
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
