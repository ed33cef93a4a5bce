//! `validate`'s checks of the tessellation methods (`tess`, `tess-reparam`,
//! declared by their registry entries): on every keyframe, both sides of
//! every shared edge have the same outer level and put the same vertices
//! on it, bit for bit, as the frame's capture holds them (the generic
//! comparisons are `crate::methods::edges`).

use std::collections::HashMap;

use super::Tess;
use crate::figures::thousands;
use crate::methods::checks::{Check, CheckFrame, CheckResult};
use crate::methods::edges::{check_edge_vertices, check_levels, shared_edges, EdgeKey, EdgeSide};
use crate::methods::RenderError;
use crate::scene::geometry::SceneGeometry;

/// The checks for a scene's geometry (`MethodInfo::checks`).
pub fn make(geo: &SceneGeometry) -> Box<dyn Check + '_> {
    Box::new(EdgeChecks {
        shared: shared_edges(&geo.patches),
    })
}

/// The scene's shared edges, found once for every keyframe.
struct EdgeChecks {
    shared: HashMap<EdgeKey, Vec<EdgeSide>>,
}

impl Check for EdgeChecks {
    /// The levels and edge vertices are read from the capture.
    fn capture(&self) -> bool {
        true
    }

    fn keyframe(&self, frame: &dyn CheckFrame, k: usize) -> Result<Vec<CheckResult>, RenderError> {
        let shared = &self.shared;
        let ctx = frame.context();
        let tess = frame
            .method()
            .downcast::<Tess>()
            .ok_or_else(|| RenderError::Request("not a tessellation method".into()))?;
        let levels = tess.read_levels(ctx)?;
        let (vertices, total) = tess.read_edge_vertices(ctx)?;
        let lv = check_levels(shared, &levels);
        let mut out = vec![CheckResult::new(
            "edge levels",
            Some(k),
            lv.bad == 0,
            lv.sides_detail("shared edges", "levels"),
        )];
        // A full capture holds some sides' vertices and not others': that
        // would read as T-junctions, so the check says it could not run.
        let full = (vertices.len() as u64) < total;
        let vx = check_edge_vertices(shared, &levels, &vertices);
        out.push(CheckResult::new(
            "edge vertices",
            Some(k),
            vx.bad == 0 && !full,
            if full {
                format!(
                    "the capture holds {} of {} edge vertices; validate at a smaller --size",
                    thousands(vertices.len() as u64),
                    thousands(total)
                )
            } else {
                vx.vertices_detail()
            },
        ));
        Ok(out)
    }
}
