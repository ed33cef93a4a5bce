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
//! output, see `untagged_cages_convert_as_before` in tests/creases.rs; it
//! refused non-manifold cages), "after" as it does now.

mod common;

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use bezier_subdiv::cage::obj::{self, CageOptions};
use bezier_subdiv::cage::sharpness::BoundaryRule;
use bezier_subdiv::cage::ImportedModel;
use glam::DVec3;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// One reference file.
#[derive(Clone)]
struct Case {
    name: String,
    model: PathBuf,
    boundary: Option<BoundaryRule>,
    creases: Option<String>,
    /// The `isolate` levels to import the case at.
    isolate: Vec<u32>,
    /// Whether each cage face is a quad (else its samples name a sub-face).
    quads: Vec<bool>,
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
    let model = root().join(kv["model"]);
    let quads = std::fs::read_to_string(&model)
        .unwrap()
        .lines()
        .filter(|l| l.split_whitespace().next() == Some("f"))
        .map(|l| l.split_whitespace().count() == 5)
        .collect();
    Case {
        name: head[2].to_string(),
        model,
        boundary: match kv["boundary"] {
            "tag" => None,
            rule => Some(rule.parse().unwrap()),
        },
        creases: (kv["creases"] != "keep").then(|| kv["creases"].to_string()),
        isolate: kv.get("isolate").map_or(vec![0], |l| {
            l.split('/').map(|n| n.parse().unwrap()).collect()
        }),
        quads,
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

fn import(case: &Case, before: bool, isolate: u32) -> ImportedModel {
    let options = CageOptions {
        boundary: if before {
            Some(BoundaryRule::EdgeAndCorner)
        } else {
            case.boundary
        },
        isolate,
        ..CageOptions::default()
    };
    obj::parse_with(&case.model, &cage_text(case, before), &options)
        .unwrap_or_else(|e| panic!("{}: {e}", case.name))
}

/// The patch and its parameters for OpenSubdiv's (face, sub-face, u, v);
/// `quad`: the face is a quad (one ptex face, `sub` 0).
fn locate(
    model: &ImportedModel,
    (face, sub, u, v): (usize, usize, f64, f64),
    quad: bool,
) -> Option<(usize, f32, f32)> {
    for (p, o) in model.origins.iter().enumerate() {
        if o.face != face || (!quad && o.sub != sub) {
            continue;
        }
        let Some(c) = o.corners_uv else {
            // A whole sub-face of an n-gon: OpenSubdiv's sub-face k is our
            // sub-quad k (u and v swapped where the patch was turned).
            let (s, t) = if o.turned { (v, u) } else { (u, v) };
            return Some((p, s as f32, t as f32));
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

/// Each sample of `case` that has a limit point: the point, where `model`
/// puts it (patch and parameters) and the patch of `classes` that holds
/// it; a sample either import leaves without a patch fails the test,
/// naming it.
fn located<'a>(
    case: &'a Case,
    model: &'a ImportedModel,
    classes: &'a ImportedModel,
) -> impl Iterator<Item = (DVec3, (usize, f32, f32), usize)> + 'a {
    case.samples
        .iter()
        .filter_map(move |&(face, sub, u, v, point)| {
            let limit = point?;
            let at = (face, sub, u, v);
            let quad = case.quads[face];
            let (Some(found), Some((pc, _, _))) =
                (locate(model, at, quad), locate(classes, at, quad))
            else {
                panic!(
                    "{}: no patch for face {face} sub {sub} at ({u}, {v})",
                    case.name
                );
            };
            Some((limit, found, pc))
        })
}

/// `classes` (the converter as it is now, at isolate 0) names each
/// sample's class and gives the diagonal both imports are measured in.
fn deviations(case: &Case, model: &ImportedModel, classes: &ImportedModel) -> Table {
    let diag = diagonal(classes);
    let mut table = Table::new();
    for (limit, (p, s, t), pc) in located(case, model, classes) {
        let dev = (model.patches[p].eval(s, t).as_dvec3() - limit).length() / diag;
        let entry = table
            .entry(classes.origins[pc].rule.class())
            .or_insert((0, 0.0));
        entry.0 += 1;
        entry.1 = entry.1.max(dev);
    }
    table
}

/// Faces OpenSubdiv leaves out are exactly the faces without a patch.
fn check_holes(case: &Case, model: &ImportedModel) {
    for &(face, sub, u, v, point) in &case.samples {
        let found = locate(model, (face, sub, u, v), case.quads[face]).is_some();
        assert_eq!(
            found,
            point.is_some(),
            "{}: face {face} hole mismatch",
            case.name
        );
    }
}

fn cases_in(dir: &str) -> Vec<Case> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "txt"))
        .collect();
    paths.sort();
    paths.iter().map(|p| read_case(p)).collect()
}

fn cases() -> Vec<Case> {
    let cases: Vec<Case> = cases_in("tests/data/osd")
        .into_iter()
        .filter(|c| c.isolate == [0])
        .collect();
    assert!(
        cases.len() >= 10,
        "reference files missing: run tools/osd-limit/run.sh"
    );
    cases
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
        let after_model = import(&case, false, 0);
        check_holes(&case, &after_model);
        let after = deviations(&case, &after_model, &after_model);
        // The converter refused non-manifold cages before.
        let info = after_model.cage.as_ref().unwrap();
        let before = (info.non_manifold_edges + info.non_manifold_vertices == 0)
            .then(|| deviations(&case, &import(&case, true, 0), &after_model));
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

/// Isolation: the deviation per class at each `isolate` level of the
/// `iso_*` cases (their samples reach into the irregular rings).
#[test]
fn isolation_converges_to_the_limit_surface() {
    let cases: Vec<Case> = cases_in("tests/data/osd")
        .into_iter()
        .filter(|c| c.isolate.len() > 1)
        .collect();
    assert!(cases.len() >= 3, "isolation reference files missing");
    println!(
        "{:<18} {:<16} {:>7} {:>9}  deviation at isolate = …",
        "case", "class", "samples", "patches"
    );
    let mut failures = Vec::new();
    for case in &cases {
        let classes = import(case, false, 0);
        let mut rows: BTreeMap<&'static str, Vec<f64>> = BTreeMap::new();
        let mut patches = Vec::new();
        for &n in &case.isolate {
            let model = import(case, false, n);
            check_holes(case, &model);
            patches.push(model.patches.len());
            for (class, (_, dev)) in deviations(case, &model, &classes) {
                rows.entry(class).or_default().push(dev);
            }
        }
        for (class, devs) in &rows {
            let shown: Vec<String> = devs.iter().map(|d| format!("{d:.1e}")).collect();
            println!(
                "{:<18} {:<16} {:>7} {:>9}  {}",
                case.name,
                class,
                "",
                patches.last().unwrap(),
                shown.join("  ")
            );
            // Each step brings the surface closer (rounding aside), exact
            // classes stay exact, and a semi-sharp crease has run out by
            // the last level (the iso_* cases' sharpness is below it).
            for (k, w) in devs.windows(2).enumerate() {
                if w[1] > w[0] * 1.01 + 1e-8 {
                    failures.push(format!(
                        "{} {class}: isolate {} {:.2e} > isolate {} {:.2e}",
                        case.name,
                        case.isolate[k + 1],
                        w[1],
                        case.isolate[k],
                        w[0]
                    ));
                }
            }
            // A crease sharper than the last level is still semi-sharp
            // there (iso_chaikin0's 5 at isolate 4): fitted, not exact.
            let last = *devs.last().unwrap();
            let run_out = f64::from(*case.isolate.last().unwrap()) >= sharpest(case);
            let exact = matches!(*class, "regular" | "crease" | "corner")
                || (*class == "semi-sharp" && run_out);
            if exact && last > 1e-5 {
                failures.push(format!("{} {class}: {last:.2e} > 1e-5", case.name));
            }
            // The irregular ring fitted to a finer surface (`fit.rs`,
            // RING_STEPS): the cube's valence-3 corners meet the issue's
            // 1e-4 at isolate 4 (2.8e-4 with Loop–Schaefer's patch alone);
            // higher valences converge slower (docs/OPENSUBDIV.md).
            if case.name == "iso_cube" && *class == "extraordinary" && last > 1e-4 {
                failures.push(format!("iso_cube extraordinary: {last:.2e} > 1e-4"));
            }
            // A crease sharper than the levels is fitted to the surface
            // refined until it runs out, not held to 4 − N steps (which
            // fitted a sharp remnant with a dart: 2.8e-3 at isolate 2,
            // with a wavy silhouette; 1.8e-3 now).
            let at2 = case.isolate.iter().position(|&n| n == 2).map(|k| devs[k]);
            if case.name == "iso_chaikin0" && *class == "semi-sharp" {
                let at2 = at2.expect("iso_chaikin0 is imported at isolate 2");
                if at2 > 2.2e-3 {
                    failures.push(format!("iso_chaikin0 at isolate 2: {at2:.2e} > 2.2e-3"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The largest sharpness the cage's `t crease` and `t corner` tags give
/// as the test imports it (with the case's `creases` override).
fn sharpest(case: &Case) -> f64 {
    let mut most = 0.0f64;
    for line in cage_text(case, false).lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        if w.len() < 3 || w[0] != "t" || !matches!(w[1], "crease" | "corner") {
            continue;
        }
        let counts: Vec<usize> = w[2].split('/').map(|n| n.parse().unwrap()).collect();
        let floats = &w[3 + counts[0]..3 + counts[0] + counts[1]];
        for f in floats {
            most = most.max(f.parse().unwrap());
        }
    }
    most
}

/// Every `catmark_*` regression shape of OpenSubdiv imports and is
/// measured against its limit surface.
#[test]
fn every_opensubdiv_shape_converts() {
    let cases = cases_in("tests/data/osd/shapes");
    assert!(cases.len() >= 80, "shape reference files missing");
    println!(
        "{:<28} {:>7} {:<16} {:>9}",
        "shape", "patches", "class", "deviation"
    );
    for case in &cases {
        let model = import(case, false, 0);
        check_holes(case, &model);
        for (class, (_, dev)) in deviations(case, &model, &model) {
            println!(
                "{:<28} {:>7} {:<16} {:>9.2e}",
                case.name,
                model.patches.len(),
                class,
                dev
            );
        }
    }
}

/// The ends of creases of sharpness 4 and more are fitted at isolate 0
/// (`fit::wanted`): a crease of sharpness 7.5 ending inside the surface of
/// `catmark_hole_test2` was converted as an infinitely sharp crease with
/// dart ends, 4.1e-2 of the model from OpenSubdiv's limit, and three
/// creases of 4.7 meeting, with a fourth ending, in `catmark_torus_creases1`
/// 6.3e-3. Fitted: 9.0e-4 and 2.1e-3.
#[test]
fn ends_of_sharp_creases_follow_the_limit() {
    let cases = cases_in("tests/data/osd/shapes");
    for (name, bound) in [
        ("catmark_hole_test2", 1e-3),
        ("catmark_torus_creases1", 2.5e-3),
    ] {
        let case = cases
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("{name}: reference missing"));
        let model = import(case, false, 0);
        let table = deviations(case, &model, &model);
        let (samples, dev) = table["semi-sharp"];
        assert!(samples > 0, "{name}: no semi-sharp samples");
        assert!(dev <= bound, "{name}: semi-sharp {dev:.2e} > {bound:.0e}");
    }
}

/// A fitted patch's largest error lies between the quarter parameters the
/// other cases sample: there the least-squares cubic across a feature
/// narrower than the face misses most, up to 3.6x what the quarters show
/// (`catmark_pyramid_creases1` 1.3e-2 of the model's size at every 1/16
/// against 3.7e-3 at the quarters). The `dense` cases sample every 1/16 of
/// shapes with fitted patches, at isolate 0 and where isolation has run
/// their creases out (exact there, between the quarters too). The bounds
/// hold what is measured over the whole surface, not at the quarters only.
/// `catmark_cube_rings` samples isolation's irregular rings on 9x9 grids
/// (iso_cube's 5x5): the rings' patches between their own quarters.
#[test]
fn fitted_patches_between_the_quarters() {
    let cases = cases_in("tests/data/osd/dense");
    assert!(cases.len() >= 4, "dense reference files missing");
    // Semi-sharp bounds at isolate 0 (measured at every 1/16, a little
    // room; at the quarters 1.7e-3, 6.5e-3, 3.7e-3, 5.8e-3).
    let bounds: HashMap<&str, f64> = [
        ("catmark_dart_edgeonly", 4.2e-3),
        ("catmark_cube_corner3", 2.2e-2),
        ("catmark_pyramid_creases1", 1.4e-2),
        ("catmark_chaikin0", 6e-3),
    ]
    .into_iter()
    .collect();
    let mut failures = Vec::new();
    println!(
        "{:<26} {:>3} {:<16} {:>7} {:>10} {:>10}",
        "case", "iso", "class", "samples", "quarters", "1/16"
    );
    for case in &cases {
        let quarters = Case {
            samples: case
                .samples
                .iter()
                .filter(|s| (s.2 * 4.0).fract() == 0.0 && (s.3 * 4.0).fract() == 0.0)
                .copied()
                .collect(),
            ..case.clone()
        };
        for &iso in &case.isolate {
            // Classes of this import: at a deeper level the rings of the
            // vertices still irregular are `extraordinary` or
            // `irregular-sharp`, everything else converted exactly.
            let model = import(case, false, iso);
            let coarse = deviations(&quarters, &model, &model);
            for (class, &(n, dev)) in &deviations(case, &model, &model) {
                println!(
                    "{:<26} {iso:>3} {class:<16} {n:>7} {:>10.2e} {dev:>10.2e}",
                    case.name, coarse[class].1
                );
                let deepest = iso > 0 && iso == *case.isolate.last().unwrap();
                let bound = match *class {
                    "regular" | "crease" | "corner" => 1e-5,
                    "semi-sharp" => bounds[case.name.as_str()],
                    // The issue's target for extraordinary faces, between
                    // the rings' quarters too (8.5e-5; 7.1e-5 at them).
                    _ if case.name == "catmark_cube_rings" && deepest => 1e-4,
                    // The rings left at the deepest level (3.7e-4 at most:
                    // cube_corner3's valence-3 corner at isolate 3).
                    _ if deepest => 4e-4,
                    _ => continue,
                };
                if dev > bound {
                    failures.push(format!(
                        "{} at isolate {iso}, {class}: {dev:.2e} > {bound:.1e}",
                        case.name
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Distances from points to a patch set (the geometric deviation: how far
/// a limit point lies from the drawn surface, wherever on it, as opposed
/// to the parametric one at the same (u, v)).
struct Nearest<'a> {
    patches: Vec<[DVec3; 16]>,
    boxes: Vec<(DVec3, DVec3)>,
    cell: f64,
    grid: HashMap<[i64; 3], Vec<usize>>,
    _model: &'a ImportedModel,
}

fn bern(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
}

fn dbern(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        -3.0 * s * s,
        3.0 * s * s - 6.0 * t * s,
        6.0 * t * s - 3.0 * t * t,
        3.0 * t * t,
    ]
}

/// The patch at (u, v) and its two partial derivatives, in f64.
fn eval64(p: &[DVec3; 16], u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
    let (bu, bv, du, dv) = (bern(u), bern(v), dbern(u), dbern(v));
    let (mut s, mut su, mut sv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for j in 0..4 {
        for i in 0..4 {
            let q = p[4 * j + i];
            s += q * (bu[i] * bv[j]);
            su += q * (du[i] * bv[j]);
            sv += q * (bu[i] * dv[j]);
        }
    }
    (s, su, sv)
}

impl<'a> Nearest<'a> {
    fn new(model: &'a ImportedModel) -> Self {
        let patches: Vec<[DVec3; 16]> = model
            .patches
            .iter()
            .map(|p| p.pts.map(|q| q.as_dvec3()))
            .collect();
        let boxes: Vec<(DVec3, DVec3)> = patches
            .iter()
            .map(|p| {
                p.iter().fold(
                    (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
                    |(lo, hi), q| (lo.min(*q), hi.max(*q)),
                )
            })
            .collect();
        let mut sizes: Vec<f64> = boxes.iter().map(|(lo, hi)| (*hi - *lo).length()).collect();
        sizes.sort_by(|a, b| a.total_cmp(b));
        let cell = sizes[sizes.len() / 2].max(1e-9);
        let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (p, (lo, hi)) in boxes.iter().enumerate() {
            let (a, b) = (Self::key(*lo, cell), Self::key(*hi, cell));
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        grid.entry([x, y, z]).or_default().push(p);
                    }
                }
            }
        }
        Nearest {
            patches,
            boxes,
            cell,
            grid,
            _model: model,
        }
    }

    fn key(p: DVec3, cell: f64) -> [i64; 3] {
        [p.x, p.y, p.z].map(|c| (c / cell).floor() as i64)
    }

    /// Closest point of patch `p` to `x`, from the start (u, v): projected
    /// Gauss–Newton steps, clamped to the domain.
    fn project(&self, p: usize, x: DVec3, (mut u, mut v): (f64, f64)) -> f64 {
        let patch = &self.patches[p];
        let mut best = f64::MAX;
        for _ in 0..30 {
            let (s, su, sv) = eval64(patch, u, v);
            let r = s - x;
            best = best.min(r.length());
            let (a, b, c) = (su.dot(su), su.dot(sv), sv.dot(sv));
            let (g0, g1) = (su.dot(r), sv.dot(r));
            let det = a * c - b * b;
            if det.abs() < 1e-300 {
                break;
            }
            let du = (c * g0 - b * g1) / det;
            let dv = (a * g1 - b * g0) / det;
            let (nu, nv) = ((u - du).clamp(0.0, 1.0), (v - dv).clamp(0.0, 1.0));
            let moved = (nu - u).abs() + (nv - v).abs();
            (u, v) = (nu, nv);
            if moved < 1e-13 {
                break;
            }
        }
        best.min((eval64(patch, u, v).0 - x).length())
    }

    /// The distance from `x` to the surface, starting at patch `p`, (u, v).
    fn distance(&self, x: DVec3, p: usize, uv: (f64, f64)) -> f64 {
        let mut best = self.project(p, x, uv);
        let r = best;
        let (a, b) = (
            Self::key(x - DVec3::splat(r), self.cell),
            Self::key(x + DVec3::splat(r), self.cell),
        );
        let mut seen = std::collections::HashSet::new();
        for gx in a[0]..=b[0] {
            for gy in a[1]..=b[1] {
                for gz in a[2]..=b[2] {
                    let Some(list) = self.grid.get(&[gx, gy, gz]) else {
                        continue;
                    };
                    for &q in list {
                        if q == p || !seen.insert(q) {
                            continue;
                        }
                        let (lo, hi) = self.boxes[q];
                        let gap = (lo - x).max(x - hi).max(DVec3::ZERO).length();
                        if gap >= best {
                            continue;
                        }
                        for start in [(0.5, 0.5), (0.1, 0.1), (0.9, 0.1), (0.9, 0.9), (0.1, 0.9)] {
                            best = best.min(self.project(q, x, start));
                        }
                    }
                }
            }
        }
        best
    }
}

/// Per class: (samples, parametric, geometric) largest deviations.
type Table2 = BTreeMap<&'static str, (usize, f64, f64)>;

fn deviations2(case: &Case, model: &ImportedModel, classes: &ImportedModel) -> Table2 {
    let diag = diagonal(classes);
    let near = Nearest::new(model);
    let mut table = Table2::new();
    for (limit, (p, s, t), pc) in located(case, model, classes) {
        let (param, _, _) = eval64(&near.patches[p], s as f64, t as f64);
        let par = (param - limit).length() / diag;
        let geo = near.distance(limit, p, (s as f64, t as f64)) / diag;
        let entry = table
            .entry(classes.origins[pc].rule.class())
            .or_insert((0, 0.0, 0.0));
        entry.0 += 1;
        entry.1 = entry.1.max(par);
        entry.2 = entry.2.max(geo);
    }
    table
}

/// Isolation measured geometrically too: how far each limit point lies
/// from the drawn surface anywhere (the parametric deviation above also
/// counts the irregular ring's patches sliding along the surface, which
/// does not show in a picture). At the deepest level every class is
/// within 1e-4 of the diagonal (the issue's target for extraordinary
/// faces at `isolate = 4`), but for the faces next to a crease still
/// semi-sharp there (iso_chaikin0: 1.5e-4 at 4, falling about fivefold a
/// level; its target is isolation to ⌈s⌉).
#[test]
fn isolation_geometric() {
    let cases: Vec<Case> = cases_in("tests/data/osd")
        .into_iter()
        .filter(|c| c.isolate.len() > 1)
        .collect();
    let mut failures = Vec::new();
    for case in &cases {
        let classes = import(case, false, 0);
        let deepest = *case.isolate.iter().max().unwrap();
        for &n in &case.isolate {
            let model = import(case, false, n);
            for (class, (k, par, geo)) in deviations2(case, &model, &classes) {
                println!(
                    "{:<18} isolate {n} {:>7} {:<16} {k:>6} param {par:.2e} geo {geo:.2e}",
                    case.name,
                    model.patches.len(),
                    class
                );
                // Not a crease sharper than the deepest level (see
                // isolation_converges_to_the_limit_surface).
                let fitted = class == "semi-sharp" && f64::from(deepest) < sharpest(case);
                if n == deepest && geo > 1e-4 && !fitted {
                    failures.push(format!(
                        "{} {class} at isolate {n}: geometric {geo:.2e} > 1e-4",
                        case.name
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// A measurement helper, not a check (hence ignored): the parametric and
/// geometric deviation of every OpenSubdiv regression shape, per class, at
/// the isolation levels in `ISO` (comma-separated, default 0), for tables
/// like docs/OPENSUBDIV.md's; `SHAPE=name` keeps the shapes whose name holds
/// it. Run it with
///
/// ```text
/// ISO=0,2 cargo test --release --test osd_reference shape_deviations -- --ignored --nocapture
/// ```
#[test]
#[ignore]
fn shape_deviations() {
    let levels: Vec<u32> = std::env::var("ISO").map_or(vec![0], |s| {
        s.split(',').map(|n| n.parse().unwrap()).collect()
    });
    let only = std::env::var("SHAPE").ok();
    for case in &cases_in("tests/data/osd/shapes") {
        if only
            .as_ref()
            .is_some_and(|s| !case.name.contains(s.as_str()))
        {
            continue;
        }
        let classes = import(case, false, 0);
        for &n in &levels {
            let model = import(case, false, n);
            for (class, (k, par, geo)) in deviations2(case, &model, &classes) {
                println!(
                    "{:<28} iso {n} {:>7} {:<16} {k:>6} param {par:.2e} geo {geo:.2e}",
                    case.name,
                    model.patches.len(),
                    class
                );
            }
        }
    }
}

/// Texture coordinates against OpenSubdiv's face-varying limit
/// (`tests/data/osd/fvar/`, each line ending with the UV limit S T): every
/// patch the import calls exact is within 1e-5 of the UV layout's size
/// (issue 39's target), under `all` every patch is exact, and the others
/// (`corners-only` near a seam: the bilinear stand-in; on an approximated
/// position patch: the same approximation) are measured and printed
/// (`--nocapture`); each case also with `isolate = 2`, where the UV cage is
/// refined as the cage is and its refined patches are regions turned in
/// the face (sub-quads run their u along the face's v, or backwards).
#[test]
fn uv_patches_follow_opensubdivs_face_varying_limit() {
    use bezier_subdiv::cage::uv::FvarRule;
    let cases = cases_in("tests/data/osd/fvar");
    assert_eq!(cases.len(), 22, "run tools/osd-limit/run.sh");
    println!("case | isolate | patches exact | worst exact | worst other, positions exact | worst other, positions approximated");
    for (case, isolate) in cases.iter().flat_map(|c| [(c, 0), (c, 2)]) {
        let text = std::fs::read_to_string(
            root()
                .join("tests/data/osd/fvar")
                .join(format!("{}.txt", case.name)),
        )
        .unwrap();
        let rule: FvarRule = text
            .lines()
            .next()
            .unwrap()
            .rsplit("fvar=")
            .next()
            .unwrap()
            .parse()
            .unwrap();
        let limits: Vec<Option<[f64; 2]>> = text
            .lines()
            .skip(1)
            .map(|l| {
                let w: Vec<&str> = l.split_whitespace().collect();
                (w.len() == 9).then(|| [w[7].parse().unwrap(), w[8].parse().unwrap()])
            })
            .collect();
        let options = CageOptions {
            boundary: case.boundary,
            fvar: rule,
            isolate,
        };
        let model = obj::parse_with(&case.model, &cage_text(case, false), &options)
            .unwrap_or_else(|e| panic!("{}: {e}", case.name));
        let uv = model.uv_patches.as_ref().expect("UV patches");
        let values = &model.uvs.as_ref().unwrap().values;
        let extent = (0..2)
            .map(|c| {
                let (lo, hi) = values.iter().fold((f64::MAX, f64::MIN), |(lo, hi), t| {
                    (lo.min(t[c] as f64), hi.max(t[c] as f64))
                });
                hi - lo
            })
            .fold(0.0, f64::max);
        // Worst of: the patches the import calls exact; the others whose
        // position patch is exact; those on an approximated position patch.
        let (mut exact_worst, mut stand_in_worst, mut shared_worst) = (0.0f64, 0.0f64, 0.0f64);
        for (&(face, sub, u, v, _), limit) in case.samples.iter().zip(&limits) {
            let Some(limit) = limit else { continue };
            let (p, s, t) = locate(&model, (face, sub, u, v), case.quads[face])
                .unwrap_or_else(|| panic!("{}: no patch at face {face} ({u}, {v})", case.name));
            let pts = uv.patches[p].map(|q| DVec3::new(q[0] as f64, q[1] as f64, 0.0));
            let got = eval64(&pts, s as f64, t as f64).0;
            let d = (got.x - limit[0]).abs().max((got.y - limit[1]).abs()) / extent;
            if uv.exact[p] {
                exact_worst = exact_worst.max(d);
            } else if model.origins[p].rule.exact() {
                stand_in_worst = stand_in_worst.max(d);
            } else {
                shared_worst = shared_worst.max(d);
            }
        }
        let exact = uv.exact.iter().filter(|&&e| e).count();
        println!(
            "{} | {isolate} | {exact}/{} | {exact_worst:.1e} | {stand_in_worst:.1e} | {shared_worst:.1e}",
            case.name,
            uv.patches.len()
        );
        assert!(
            exact_worst <= 1e-5,
            "{} (isolate {isolate}): {exact_worst:e}",
            case.name
        );
        if isolate > 0 {
            // Refined where the UVs need it (their layout's extraordinary
            // vertices), as OpenSubdiv's adaptive refinement does: every
            // patch on an exact position patch within the target at every
            // sample, the ones the import still calls approximate included
            // (docs/OPENSUBDIV.md).
            assert!(
                stand_in_worst <= 1e-5,
                "{} (isolate {isolate}): {stand_in_worst:e} off the face-varying limit",
                case.name
            );
            continue;
        }
        // Under `all` every patch is exact; under `corners-only` as many as
        // today (docs/OPENSUBDIV.md): grid_uv by the stencils, the
        // helmet's islands, and next to seams by the UV cage's conversion
        // (all but the patches at its extraordinary vertices).
        let expected = match case.name.as_str() {
            _ if rule == FvarRule::All => uv.patches.len(),
            "catmark_cube_corners-only" => 2,
            "catmark_fvar_bound0_corners-only" | "catmark_fvar_bound1_corners-only" => 12,
            "catmark_fvar_bound2_corners-only" => 8,
            "catmark_fvar_bound3_corners-only" => 6,
            "catmark_fvar_bound4_corners-only" => 1,
            "catmark_fvar_project0_corners-only" => 0,
            "catmark_helmet_corners-only" => 58,
            "catmark_torus_corners-only" => 32,
            "grid_uv_corners-only" => 16,
            "ngon_uv_corners-only" => 20,
            other => panic!("no expected count for {other}"),
        };
        assert!(
            exact >= expected,
            "{}: {exact} exact patches, {expected} before",
            case.name
        );
    }
}
