//! `import`: read a cage or patch file, summarise it, optionally write the
//! patches as `.bpt` plus a `.bpt.json` sidecar telling where each came from.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use glam::Vec3;

use crate::files::{commit, stage, temp_sibling};
use crate::patch::bezier::BezierPatch;
use crate::scene::file::load_model;
use crate::scene::{bpt, ImportedModel, PatchOrigin};

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
    s += &format!("  patches         {}\n", model.patches.len());
    if let Some((lo, hi)) = BezierPatch::bounds(&model.patches) {
        let f = |v: Vec3| format!("[{:.4}, {:.4}, {:.4}]", v.x, v.y, v.z);
        s += &format!("  control box     {} .. {}\n", f(lo), f(hi));
    }
    for w in &model.warnings {
        s += &format!("  warning: {w}\n");
    }
    s
}

/// The sidecar JSON: one entry per patch, in file order.
pub fn sidecar_json(origins: &[PatchOrigin]) -> String {
    let entries: Vec<serde_json::Value> = origins
        .iter()
        .map(|o| {
            serde_json::json!({
                "face": o.face,
                "corners_uv": o.corners_uv.map(|c| c.map(|uv| [uv[0] as f64, uv[1] as f64])),
            })
        })
        .collect();
    let doc = serde_json::json!({ "patches": entries });
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
pub fn run(input: &Path, out: Option<&Path>) -> anyhow::Result<String> {
    let model = load_model(input)?;
    let mut text = summary(input, &model);
    if let Some(out) = out {
        let tmp_bpt = temp_sibling(out);
        bpt::write(&tmp_bpt, &model.patches)?;
        let mut staged = vec![(tmp_bpt, out.to_path_buf())];
        if !model.origins.is_empty() {
            let side = sidecar_path(out);
            match stage(&side, sidecar_json(&model.origins).as_bytes()) {
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
