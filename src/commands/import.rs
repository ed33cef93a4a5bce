//! `import`: read a cage or patch file, summarise it, optionally write the
//! patches as `.bpt` plus a `.bpt.json` sidecar telling where each came from.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use glam::Vec3;

use crate::cage::obj::CageOptions;
use crate::cage::{CageInfo, ImportedModel, PatchOrigin, RuleSource};
use crate::files::{commit, stage, temp_sibling};
use crate::patch::bezier::BezierPatch;
use crate::patch::shading::{self, SHADING_BYTES_PER_PATCH};
use crate::scene::bpt;
use crate::scene::geometry::load_model_with;

/// The summary `import` prints.
pub fn summary(path: &Path, model: &ImportedModel) -> String {
    let kind = if model.origins.is_empty() {
        "Bézier patch file"
    } else {
        "Catmull-Clark cage"
    };
    let mut s = format!("{}: {kind}\n", path.display());
    if !model.origins.is_empty() {
        let faces = model.origins.iter().map(|o| o.face + 1).max().unwrap_or(0);
        let non_quad = model
            .origins
            .iter()
            .filter(|o| o.corners_uv.is_none())
            .count();
        s += &format!("  cage faces      {faces}\n");
        if non_quad > 0 {
            s += &format!("  patches of non-quad faces {non_quad}\n");
        }
    }
    if let Some(info) = &model.cage {
        s += &cage_lines(info);
        if let Some(uv) = &model.uv_patches {
            let exact = uv.exact.iter().filter(|&&e| e).count();
            s += &format!(
                "  UV patches      {} ({}): {exact} of {} exact (the others approximated, docs/OPENSUBDIV.md)\n",
                uv.patches.len(),
                uv.rule.name(),
                uv.patches.len()
            );
        }
        s += &format!("  patch rules     {}\n", rule_counts(&model.origins));
    }
    if let Some(map) = &model.albedo {
        s += &format!(
            "  albedo map      {} (named at {})\n",
            map.path.display(),
            map.from
        );
    }
    s += &format!("  patches         {}\n", model.patches.len());
    if let Some((lo, hi)) = BezierPatch::bounds(&model.patches) {
        let f = |v: Vec3| format!("[{:.4}, {:.4}, {:.4}]", v.x, v.y, v.z);
        s += &format!("  control box     {} .. {}\n", f(lo), f(hi));
    }
    if !model.origins.is_empty() {
        if let Some((geometric, tangent)) = normal_jumps(model) {
            s += &format!(
                "  shading normals largest jump across smooth patch edges: {geometric:.3}° from the \
                 patches' own derivatives, {tangent:.4}° from the tangent patches \
                 ({SHADING_BYTES_PER_PATCH} bytes per patch)\n"
            );
        }
    }
    for w in &model.warnings {
        s += &format!("  warning: {w}\n");
    }
    s
}

fn cage_lines(info: &CageInfo) -> String {
    let from = match info.boundary_from {
        RuleSource::Tag(line) => format!("`t interpolateboundary` at line {line}"),
        RuleSource::Option => "option".into(),
        RuleSource::Default => "default; the file has no interpolateboundary tag".into(),
    };
    let mut s = format!(
        "  boundary rule   {} ({from}), {} boundary edges\n",
        info.boundary, info.boundary_edges
    );
    if info.holes > 0 {
        s += &format!(
            "  holes           {} faces at the boundary give no patch\n",
            info.holes
        );
    }
    if info.sharp_edges + info.semi_sharp_edges + info.corners > 0 {
        s += &format!(
            "  creases         {} infinitely sharp edges, {} semi-sharp (approximated), {} corners\n",
            info.sharp_edges, info.semi_sharp_edges, info.corners
        );
    }
    if info.non_manifold_edges + info.non_manifold_vertices > 0 {
        s += &format!(
            "  non-manifold    {} edges, {} vertices\n",
            info.non_manifold_edges, info.non_manifold_vertices
        );
    }
    if let Some(isolation) = &info.isolation {
        s += &format!(
            "  isolation       {isolation}
"
        );
    }
    if let Some(uv) = &info.uv {
        s += &format!(
            "  texture coords  {} values, seams along {} edges through {} vertices\n",
            uv.values, uv.seam_edges, uv.seam_vertices
        );
    }
    s
}

/// Patches per conversion class, and how many are exact.
fn rule_counts(origins: &[PatchOrigin]) -> String {
    let classes = [
        "regular",
        "crease",
        "corner",
        "extraordinary",
        "irregular-sharp",
        "semi-sharp",
    ];
    let mut parts: Vec<String> = Vec::new();
    for c in classes {
        let n = origins.iter().filter(|o| o.rule.class() == c).count();
        if n > 0 {
            parts.push(format!("{c} {n}"));
        }
    }
    let exact = origins.iter().filter(|o| o.rule.exact()).count();
    format!("{} (exact: {exact} of {})", parts.join(", "), origins.len())
}

/// The largest angle between the normals on the two sides of a smooth
/// patch edge, in degrees: from the patches' own derivatives and from the
/// shading (tangent) patches. `None` when no smooth edge is shared.
pub fn normal_jumps(model: &ImportedModel) -> Option<(f64, f64)> {
    let feature = |p: usize, k: usize| {
        model
            .origins
            .get(p)
            .is_some_and(|o| o.rule.feature_edges & (1 << k) != 0)
    };
    let pairs = shading::shared_edges(&model.patches, &feature);
    let tangents = model.shading_patches();
    let geometric = shading::largest_jump(&pairs, 16, &|p, u, v| model.patches[p].normal(u, v))?;
    let tangent = shading::largest_jump(&pairs, 16, &|p, u, v| tangents[p].normal(u, v))?;
    Some((geometric.degrees, tangent.degrees))
}

/// The sidecar JSON: the cage's boundary rule, then one entry per patch in
/// file order: its cage face (and sub-quad `sub` for a refined face), the
/// face coordinates of its corners, its conversion class (`rule`), whether
/// it is exactly OpenSubdiv's limit surface, the vertex rule at each corner
/// and which of its edges (corner k → k + 1) are creases or boundaries.
pub fn sidecar_json(model: &ImportedModel) -> String {
    let entries: Vec<serde_json::Value> = model
        .origins
        .iter()
        .map(|o| {
            let corners: Vec<serde_json::Value> = o
                .rule
                .corners
                .iter()
                .map(|c| {
                    serde_json::json!({
                        "rule": c.rule.name(),
                        "valence": c.valence,
                        "sector": c.sector,
                        "semi_sharp": c.semi_sharp,
                    })
                })
                .collect();
            let features: Vec<bool> = (0..4)
                .map(|k| o.rule.feature_edges & (1 << k) != 0)
                .collect();
            serde_json::json!({
                "face": o.face,
                "sub": o.sub,
                "corners_uv": o.corners_uv.map(|c| c.map(|uv| [uv[0] as f64, uv[1] as f64])),
                "rule": o.rule.class(),
                "exact": o.rule.exact(),
                "corners": corners,
                "feature_edges": features,
            })
        })
        .collect();
    let boundary = model.cage.as_ref().map(|c| {
        let (from, line) = match c.boundary_from {
            RuleSource::Tag(line) => ("tag", Some(line)),
            RuleSource::Option => ("option", None),
            RuleSource::Default => ("default", None),
        };
        serde_json::json!({ "rule": c.boundary.name(), "from": from, "line": line })
    });
    let uv = model.cage.as_ref().and_then(|c| c.uv).map(|u| {
        serde_json::json!({
            "values": u.values,
            "seam_edges": u.seam_edges,
            "seam_vertices": u.seam_vertices,
        })
    });
    let albedo = model
        .albedo
        .as_ref()
        .map(|m| serde_json::json!({ "path": m.path.display().to_string(), "from": m.from }));
    let doc = serde_json::json!({
        "boundary": boundary,
        "uv": uv,
        "albedo_map": albedo,
        "semi_sharp": "sharpness >= 1 is converted as infinitely sharp; below 1 the points near the vertex are smooth + s x (sharp - smooth)",
        "patches": entries,
    });
    serde_json::to_string_pretty(&doc).expect("JSON of plain values") + "\n"
}

/// The sidecar path for a `.bpt` output: `PATCHES.bpt.json`.
pub fn sidecar_path(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".json");
    PathBuf::from(s)
}

/// Imports `input`; with `out`, writes the patches (and, for cages, the
/// sidecar). Both files are written under temporary names and renamed only
/// when both are complete, so a failure leaves nothing half-written.
pub fn run(input: &Path, out: Option<&Path>, options: &CageOptions) -> anyhow::Result<String> {
    let model = load_model_with(input, options)?;
    let mut text = summary(input, &model);
    if let Some(out) = out {
        // Checked under the name asked for: the file is written under
        // another one first.
        bpt::check(out, &model.patches)?;
        let tmp_bpt = temp_sibling(out);
        bpt::write(&tmp_bpt, &model.patches)?;
        let mut staged = vec![(tmp_bpt, out.to_path_buf())];
        if !model.origins.is_empty() {
            let side = sidecar_path(out);
            match stage(&side, sidecar_json(&model).as_bytes()) {
                Ok(tmp) => staged.push((tmp, side)),
                Err(e) => {
                    let _ = std::fs::remove_file(&staged[0].0);
                    return Err(e).with_context(|| format!("writing {}", side.display()));
                }
            }
        }
        commit(&staged).map_err(|(file, e)| {
            anyhow::Error::new(e).context(format!("writing {}", file.display()))
        })?;
        for (_, to) in &staged {
            text += &format!("  wrote           {}\n", to.display());
        }
    }
    Ok(text)
}
