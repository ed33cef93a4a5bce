//! The cage converter against OpenSubdiv 3.5's limit surface.
//!
//! `tests/data/osd/*.txt` hold OpenSubdiv's limit points at chosen (face,
//! u, v) of the test cages, written by `tools/osd-limit/run.sh` (a small
//! program of ours against Debian's libosd-dev); this test needs no
//! OpenSubdiv. Each file's first line names its case: the model, the
//! boundary rule, an optional rewrite of every crease's sharpness, and the
//! sample set. Deviations are measured in units of the diagonal of the
//! model's control-point box, per conversion class (`PatchRule::class`).
//!
//! `cargo test --release --test osd_reference -- --nocapture` prints the
//! table: "before" imports the cage as the converter did before tags were
//! read (tags dropped, edge-and-corner: bit for bit the old converter's
//! output, see `untagged_cages_convert_as_before` in tests/import.rs; it
//! refused non-manifold cages), "after" as it does now.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use bezier_subdiv::scene::obj::{self, CageOptions};
use bezier_subdiv::scene::sharpness::BoundaryRule;
use bezier_subdiv::scene::ImportedModel;
use glam::DVec3;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// One reference file.
struct Case {
    name: String,
    model: PathBuf,
    boundary: Option<BoundaryRule>,
    creases: Option<String>,
    /// (face, sub-face, u, v, limit point or `None` for a hole).
    samples: Vec<(usize, usize, f64, f64, Option<DVec3>)>,
}

fn read_case(path: &Path) -> Case {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
    assert_eq!(&head[..2], ["#", "case"], "{}", path.display());
    let kv: HashMap<&str, &str> = head[3..].iter().filter_map(|w| w.split_once('=')).collect();
    let samples = lines
        .map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            let n = |i: usize| w[i].parse::<f64>().unwrap();
            let point = (w[4] != "hole").then(|| DVec3::new(n(4), n(5), n(6)));
            (
                w[0].parse().unwrap(),
                w[1].parse().unwrap(),
                n(2),
                n(3),
                point,
            )
        })
        .collect();
    Case {
        name: head[2].to_string(),
        model: root().join(kv["model"]),
        boundary: match kv["boundary"] {
            "tag" => None,
            rule => Some(rule.parse().unwrap()),
        },
        creases: (kv["creases"] != "keep").then(|| kv["creases"].to_string()),
        samples,
    }
}

/// The cage text of a case: every crease's sharpness replaced when asked
/// (as `run.sh` does), every tag dropped for the "before" import.
fn cage_text(case: &Case, before: bool) -> String {
    let text = std::fs::read_to_string(&case.model).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        let mut words: Vec<&str> = line.split_whitespace().collect();
        if words.first() == Some(&"t") {
            if before
                && matches!(
                    words.get(1),
                    Some(&"crease" | &"corner" | &"interpolateboundary")
                )
            {
                continue;
            }
            if let (Some(s), Some(&"crease")) = (&case.creases, words.get(1)) {
                *words.last_mut().unwrap() = s;
                out += &words.join(" ");
                out.push('\n');
                continue;
            }
        }
        out += line;
        out.push('\n');
    }
    out
}

fn import(case: &Case, before: bool) -> ImportedModel {
    let options = CageOptions {
        boundary: if before {
            Some(BoundaryRule::EdgeAndCorner)
        } else {
            case.boundary
        },
    };
    obj::parse_with(&case.model, &cage_text(case, before), &options)
        .unwrap_or_else(|e| panic!("{}: {e}", case.name))
}

/// The patch and its parameters for OpenSubdiv's (face, sub-face, u, v).
fn locate(
    model: &ImportedModel,
    face: usize,
    sub: usize,
    u: f64,
    v: f64,
) -> Option<(usize, f32, f32)> {
    for (p, o) in model.origins.iter().enumerate() {
        if o.face != face {
            continue;
        }
        let Some(c) = o.corners_uv else {
            // A patch of an n-gon: OpenSubdiv's sub-face k is our sub-quad k.
            if o.sub == sub {
                return Some((p, u as f32, v as f32));
            }
            continue;
        };
        // (u, v) = c0 + s (c1 − c0) + t (c3 − c0); the sub-squares are axis
        // aligned, so each of s and t depends on one coordinate.
        let d = |a: [f32; 2]| [a[0] as f64 - c[0][0] as f64, a[1] as f64 - c[0][1] as f64];
        let (e1, e3, q) = (d(c[1]), d(c[3]), [u - c[0][0] as f64, v - c[0][1] as f64]);
        let det = e1[0] * e3[1] - e1[1] * e3[0];
        let s = (q[0] * e3[1] - q[1] * e3[0]) / det;
        let t = (e1[0] * q[1] - e1[1] * q[0]) / det;
        if (-1e-9..=1.0 + 1e-9).contains(&s) && (-1e-9..=1.0 + 1e-9).contains(&t) {
            return Some((p, s as f32, t as f32));
        }
    }
    None
}

fn diagonal(model: &ImportedModel) -> f64 {
    let mut lo = DVec3::splat(f64::MAX);
    let mut hi = DVec3::splat(f64::MIN);
    for q in model.patches.iter().flat_map(|p| p.pts.iter()) {
        lo = lo.min(q.as_dvec3());
        hi = hi.max(q.as_dvec3());
    }
    (hi - lo).length()
}

/// Largest deviation per class, over the samples that have a patch.
type Table = BTreeMap<&'static str, (usize, f64)>;

/// `classes` (the converter as it is now) names each sample's class and
/// gives the diagonal both imports are measured in.
fn deviations(case: &Case, model: &ImportedModel, classes: &ImportedModel) -> Table {
    let diag = diagonal(classes);
    let mut table = Table::new();
    for &(face, sub, u, v, point) in &case.samples {
        let Some(limit) = point else { continue };
        let (Some((p, s, t)), Some((pc, _, _))) = (
            locate(model, face, sub, u, v),
            locate(classes, face, sub, u, v),
        ) else {
            panic!(
                "{}: no patch for face {face} sub {sub} at ({u}, {v})",
                case.name
            );
        };
        let dev = (model.patches[p].eval(s, t).as_dvec3() - limit).length() / diag;
        let entry = table
            .entry(classes.origins[pc].rule.class())
            .or_insert((0, 0.0));
        entry.0 += 1;
        entry.1 = entry.1.max(dev);
    }
    table
}

fn cases() -> Vec<Case> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join("tests/data/osd"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "txt"))
        .collect();
    paths.sort();
    assert!(
        paths.len() >= 10,
        "reference files missing: run tools/osd-limit/run.sh"
    );
    paths.iter().map(|p| read_case(p)).collect()
}

/// Exact classes must match OpenSubdiv to float precision; the
/// approximations must stay within what they measure today.
#[test]
fn converter_matches_opensubdiv() {
    // Upper bounds for the approximated classes, per case (measured, with a
    // little room); a class not listed must not appear.
    let approx: HashMap<(&str, &str), f64> = [
        (("cube", "extraordinary"), 8e-3),
        (("xord_interior", "irregular-sharp"), 2.1e-2),
        (("pole64", "extraordinary"), 1.5e-2),
        (("helmet", "semi-sharp"), 3e-4),
        (("pawn", "extraordinary"), 4.5e-3),
        (("pawn", "semi-sharp"), 2.5e-4),
        (("car", "extraordinary"), 3e-3),
        (("car", "irregular-sharp"), 5e-4),
        (("car", "semi-sharp"), 2.5e-3),
        (("car_sharp", "extraordinary"), 3e-3),
        (("car_sharp", "irregular-sharp"), 2.5e-3),
        (("grid_crease", "irregular-sharp"), 1e-3),
        (("grid_crease_edge", "irregular-sharp"), 1e-3),
        (("grid_crease_none", "irregular-sharp"), 1.2e-3),
        (("grid_semi", "semi-sharp"), 8e-4),
        (("cubes_touching", "extraordinary"), 4e-3),
        (("cubes_touching", "irregular-sharp"), 1.5e-2),
    ]
    .into_iter()
    .collect();
    let mut failures = Vec::new();
    println!(
        "{:<18} {:<16} {:>7} {:>10} {:>10}",
        "case", "class", "samples", "before", "after"
    );
    for case in cases() {
        let after_model = import(&case, false);
        // Faces OpenSubdiv leaves out are exactly the faces without a patch.
        for &(face, sub, u, v, point) in &case.samples {
            let found = locate(&after_model, face, sub, u, v).is_some();
            assert_eq!(
                found,
                point.is_some(),
                "{}: face {face} hole mismatch",
                case.name
            );
        }
        let after = deviations(&case, &after_model, &after_model);
        // The converter refused non-manifold cages before.
        let info = after_model.cage.as_ref().unwrap();
        let before = (info.non_manifold_edges + info.non_manifold_vertices == 0)
            .then(|| deviations(&case, &import(&case, true), &after_model));
        for (class, &(n, dev)) in &after {
            let was = before.as_ref().and_then(|b| b.get(class)).map(|&(_, d)| d);
            let shown = was.map_or("refused".into(), |d| format!("{d:.2e}"));
            println!(
                "{:<18} {:<16} {n:>7} {shown:>10} {dev:>10.2e}",
                case.name, class
            );
            // Reading the tags never makes a class worse.
            if was.is_some_and(|w| dev > w * 1.001 + 1e-9) {
                failures.push(format!(
                    "{} {class}: {dev:.2e} is worse than {shown} before",
                    case.name
                ));
            }
            let bound = match *class {
                "regular" | "crease" | "corner" => 1e-5,
                other => match approx.get(&(case.name.as_str(), other)) {
                    Some(&b) => b,
                    None => {
                        failures.push(format!("{}: unexpected class {other}", case.name));
                        continue;
                    }
                },
            };
            if dev > bound {
                failures.push(format!("{} {class}: {dev:.2e} > {bound:.0e}", case.name));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
