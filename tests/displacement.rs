//! Displaced surfaces on the CPU (issue 40): the oracle's displaced mesh of
//! scenes/displaced.toml is watertight (every open edge lies on a model's
//! own boundary) across UV seams, poles and a mirrored instance, with
//! wedges, and shows cracks without them; shared edges are displaced to
//! the same bits from both sides; a constant map draws what the undisplaced
//! surface draws, offset.

mod common;

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use glam::Vec3;

use bezier_subdiv::patch::bezier::BezierPatch;
use bezier_subdiv::patch::oracle::{
    subdivide_displaced, subdivide_parallel, triangulate, triangulate_surfaces, Triangle,
};
use bezier_subdiv::patch::view::{ViewParams, FLAG_ANISO, FLAG_BACKFACE_CULL, FLAG_FRUSTUM_CULL};
use bezier_subdiv::scene::desc::Scene;
use bezier_subdiv::scene::displaced::Displaced;
use bezier_subdiv::scene::displacement::edge_point;
use bezier_subdiv::scene::geometry::SceneGeometry;

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
}

fn displaced_scene() -> (Scene, SceneGeometry) {
    let scene = Scene::load(&scene_path("displaced.toml")).unwrap();
    let geo = scene.geometry().unwrap();
    (scene, geo)
}

fn curve_bits(c: &[Vec3; 4]) -> [[u32; 3]; 4] {
    c.map(|p| p.to_array().map(f32::to_bits))
}

/// Every pair of sides of one boundary curve (collapsed edges included).
fn edge_pairs(patches: &[BezierPatch]) -> Vec<common::edges::SharedEdge> {
    common::edges::shared_edges(patches.len(), |k, e| {
        let c = patches[k].edge(e);
        Some((curve_bits(&c), curve_bits(&[c[3], c[2], c[1], c[0]])))
    })
}

/// (patch, edge) sides that another side shares (collapsed edges aside).
fn shared_sides(patches: &[BezierPatch]) -> HashSet<(u32, usize)> {
    let mut out = HashSet::new();
    for se in common::edges::shared_edges(patches.len(), |k, e| {
        let c = patches[k].edge(e);
        if c.iter().all(|q| *q == c[0]) {
            return None;
        }
        Some((curve_bits(&c), curve_bits(&[c[3], c[2], c[1], c[0]])))
    }) {
        out.insert(se.a);
        out.insert(se.b);
    }
    out
}

/// Open edges of `tris` that do not lie on an unshared side of a base
/// patch: cracks.
fn cracks(patches: &[BezierPatch], tris: &[Triangle]) -> usize {
    common::edges::cracks(tris, &shared_sides(patches)).len()
}

/// Frame 0 of the scene and a view of it all from afar, each with `iso`
/// and `aniso` splits; no culling (every edge is checked).
fn views(scene: &Scene, geo: &SceneGeometry) -> Vec<ViewParams> {
    let cams = [
        scene.frame_camera(0).unwrap(),
        common::cameras::around(&geo.patches)[0],
    ];
    let mut out = Vec::new();
    for cam in cams {
        for aniso in [false, true] {
            let mut vp = cam.view_params(640, 360, 1.0, 0.5);
            vp.flags &= !(FLAG_FRUSTUM_CULL | FLAG_BACKFACE_CULL);
            if aniso {
                vp.flags |= FLAG_ANISO;
            }
            out.push(vp);
        }
    }
    out
}

/// The displaced oracle mesh is closed wherever the base surface is, with
/// wedges; without them it cracks (the test sees cracks), and the
/// displacement does move the surface and refine it.
#[test]
fn displaced_meshes_are_watertight_across_seams_poles_and_mirrors() {
    let (scene, geo) = displaced_scene();
    let dc = Displaced::of(&geo).expect("displaced models");
    for vp in views(&scene, &geo) {
        let res = subdivide_displaced(&dc, &vp, 2);
        let plain = subdivide_parallel(&geo.patches, &geo.flags, &vp, 2);
        let tris = triangulate_surfaces(&dc, &res.ready, true);
        let open = cracks(&geo.patches, &tris);
        let without = cracks(&geo.patches, &triangulate_surfaces(&dc, &res.ready, false));
        let moved = {
            let flat = triangulate(&geo.patches, &res.ready, true);
            flat.iter().zip(&tris).filter(|(a, b)| a.v != b.v).count()
        };
        println!(
            "aniso {}: {} ready nodes ({} undisplaced), {} triangles, {} moved, {} cracks, {} without wedges",
            vp.has(FLAG_ANISO),
            res.ready.len(),
            plain.ready.len(),
            tris.len(),
            moved,
            open,
            without
        );
        assert_eq!(open, 0, "cracks in the displaced mesh");
        assert!(without > 0, "without wedges the test must see cracks");
        assert!(moved > tris.len() / 2, "the displacement moves the surface");
        assert!(res.ready.len() > plain.ready.len(), "bumps need more nodes");
    }
}

/// Every point of every shared edge (at the dyadic parameters nodes have,
/// down to depth 6) is displaced to the same bits from both sides: across
/// UV seams, where the two sides' texture coordinates differ, across the
/// mirrored instance, and at poles. The checks see seams: some shared
/// edges' UVs differ between the sides.
#[test]
fn shared_edges_are_displaced_identically_from_both_sides() {
    let (_, geo) = displaced_scene();
    let dc = Displaced::of(&geo).unwrap();
    let patches = &geo.patches;
    let shared = edge_pairs(patches);
    let (mut points, mut seam_points, mut collapsed, mut moved) = (0u64, 0u64, 0u64, 0u64);
    let along = |e: usize, s: f32| edge_point(e, s);
    for se in &shared {
        let ((pa, ea), (pb, eb)) = (se.a, se.b);
        let (pa, pb) = (pa as usize, pb as usize);
        if dc.model_of(pa).is_none() {
            continue;
        }
        let pole = {
            let c = patches[pa].edge(ea);
            c.iter().all(|q| *q == c[0])
        };
        for k in 0..=64u32 {
            let s = k as f32 / 64.0;
            let sb = if se.reversed { 1.0 - s } else { s };
            let (ua, va) = along(ea, s);
            let (ub, vb) = along(eb, sb);
            let (a, b) = (dc.point(pa, ua, va), dc.point(pb, ub, vb));
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits),
                "patch {pa} edge {ea} and patch {pb} edge {eb} at {s}: {a} vs {b}"
            );
            moved += (a != patches[pa].eval(ua, va)) as u64;
            points += 1;
            seam_points += (geo.surface_uv(pa, ua, va) != geo.surface_uv(pb, ub, vb)) as u64;
            collapsed += pole as u64;
        }
    }
    println!(
        "{points} edge points ({moved} moved), {seam_points} on UV seams, {collapsed} on poles"
    );
    assert!(
        seam_points > 1000 && collapsed > 100,
        "the scene must have seams and poles"
    );
    assert!(moved > points / 2, "the edges must be displaced");
}

/// Writes a 16-bit grey PNG of `w × h` heights `h(x, y)`.
fn write_height_map(path: &Path, w: u32, h: u32, f: impl Fn(u32, u32) -> u16) {
    let img = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(w, h, |x, y| {
        image::Luma([f(x, y)])
    });
    img.save(path).unwrap();
}

/// A scene of the teapot, the torus (seams) and the pillow, displaced by
/// `map` (or not), in a temporary directory.
fn small_scene(dir: &Path, displacement: Option<&str>) -> (Scene, SceneGeometry) {
    let models = scene_path("models");
    let disp = displacement
        .map(|d| format!("displacement = {{ map = \"{d}\", scale = 0.1, bias = 0.02 }}\n"))
        .unwrap_or_default();
    let text = format!(
        "[camera]\nposition = [4.0, -9.0, 5.0]\ntarget = [1.0, 0.0, 0.5]\n\
         [[model]]\nfile = \"{m}/teapot.bpt\"\n{disp}\
         [[model]]\nfile = \"{m}/catmark_torus.obj\"\n{disp}[[model.instance]]\ntranslate = [4.0, 0.0, 0.5]\n\
         [[model]]\nfile = \"{m}/pillow.bpt\"\ntwo_sided = true\n{disp}[[model.instance]]\ntranslate = [-3.0, 2.0, 0.5]\n",
        m = models.display()
    );
    let path = dir.join(format!("scene_{}.toml", displacement.is_some()));
    std::fs::write(&path, text).unwrap();
    let scene = Scene::load(&path).unwrap();
    let geo = scene.geometry().unwrap();
    (scene, geo)
}

/// A constant map costs no nodes: the ready set is the undisplaced one
/// node for node, and every vertex moves by the constant along its normal.
#[test]
fn a_constant_map_draws_the_undisplaced_nodes_offset() {
    let dir = common::output_dir("displacement_constant");
    write_height_map(&dir.join("flat.png"), 16, 8, |_, _| 32768);
    let (scene, plain) = small_scene(&dir, None);
    let (_, geo) = small_scene(&dir, Some("flat.png"));
    let dc = Displaced::of(&geo).unwrap();
    let h = 32768.0f32 / 65535.0;
    let d = 0.02 + 0.1 * h;
    let mut vp = scene
        .frame_camera(0)
        .unwrap()
        .view_params(640, 360, 1.0, 0.5);
    vp.flags &= !(FLAG_FRUSTUM_CULL | FLAG_BACKFACE_CULL);
    for aniso in [false, true] {
        if aniso {
            vp.flags |= FLAG_ANISO;
        }
        let want = subdivide_parallel(&plain.patches, &plain.flags, &vp, 2);
        let got = subdivide_displaced(&dc, &vp, 2);
        assert_eq!(got.ready, want.ready, "aniso {aniso}");
        let moved = triangulate_surfaces(&dc, &got.ready, true);
        let base = triangulate(&geo.patches, &got.ready, true);
        let mut worst = 0.0f32;
        for (a, b) in moved.iter().zip(&base) {
            for k in 0..3 {
                worst = worst.max(((a.v[k] - b.v[k]).length() - d).abs());
            }
        }
        assert!(worst < 1e-5, "offsets differ from {d} by up to {worst}");
        println!(
            "aniso {aniso}: {} nodes as undisplaced, offsets within {worst:e}",
            got.ready.len()
        );
    }
}

/// Bad displacement input is an error naming the model and what is wrong,
/// never a panic: a missing map, a map whose sides are not powers of two,
/// not a PNG, a scale that is not finite, PN triangles.
#[test]
fn bad_displacement_input_is_a_clear_error() {
    let dir = common::output_dir("displacement_bad");
    write_height_map(&dir.join("odd.png"), 12, 8, |x, _| (x * 1000) as u16);
    std::fs::write(dir.join("text.png"), "not a png").unwrap();
    let teapot = scene_path("models/teapot.bpt");
    let load = |disp: &str, surface: &str| {
        let text = format!(
            "[camera]\nposition = [4.0, -9.0, 5.0]\ntarget = [0.0, 0.0, 0.5]\n\
             [[model]]\nname = \"pot\"\nfile = \"{}\"\n{surface}displacement = {disp}\n",
            teapot.display()
        );
        let path = dir.join("bad.toml");
        std::fs::write(&path, text).unwrap();
        Scene::load(&path)
            .and_then(|s| s.geometry().map(|_| ()))
            .unwrap_err()
            .to_string()
    };
    let cases = [
        (r#"{ map = "missing.png", scale = 0.1 }"#, "", "missing.png"),
        (r#"{ map = "odd.png", scale = 0.1 }"#, "", "powers of two"),
        (
            r#"{ map = "text.png", scale = 0.1 }"#,
            "",
            "not a readable PNG",
        ),
        (r#"{ map = "odd.png", scale = nan }"#, "", "must be finite"),
        (r#"{ map = "odd.png" }"#, "", "scale"),
        (
            r#"{ map = "odd.png", scale = 0.1 }"#,
            "surface = \"pn-triangles\"\n",
            "PN triangles",
        ),
    ];
    for (disp, surface, want) in cases {
        let err = load(disp, surface);
        assert!(err.contains(want), "{disp}: {err}");
        assert!(
            err.contains("pot") || err.contains("bad.toml"),
            "{disp}: {err}"
        );
    }
}

/// Both sides of every shared edge bound its displacement with the same
/// bits, at every depth down to 6 and for every segment (the edge tier's
/// decision depends on it: a bound that differed would open a crack), and
/// the bound is computed from the edge owner's UVs also where the sides'
/// UVs differ (seams).
#[test]
fn shared_edges_get_the_same_displacement_bound_from_both_sides() {
    let (_, geo) = displaced_scene();
    let dc = Displaced::of(&geo).unwrap();
    let patches = &geo.patches;
    let shared = edge_pairs(patches);
    let (mut checked, mut nonzero) = (0u64, 0u64);
    for se in &shared {
        let ((pa, ea), (pb, eb)) = (se.a, se.b);
        let Some(m) = dc.model_of(pa as usize) else {
            continue;
        };
        for l in 0..=6u32 {
            for k in 0..(1u32 << l) {
                let kb = if se.reversed { (1 << l) - 1 - k } else { k };
                let a = common::edges::edge_node(pa, ea, l, k);
                let b = common::edges::edge_node(pb, eb, l, kb);
                let ra = dc.edge_reach(pa as usize, m, a, ea);
                let rb = dc.edge_reach(pb as usize, m, b, eb);
                assert_eq!(
                    ra.to_bits(),
                    rb.to_bits(),
                    "patch {pa} edge {ea} / patch {pb} edge {eb}, depth {l} segment {k}"
                );
                checked += 1;
                nonzero += (ra > 0.0) as u64;
            }
        }
    }
    println!("{checked} edge segments, {nonzero} with a bound above 0");
    assert!(nonzero > checked / 2);
}

/// The drawn point of a ready node at (x, y) of its domain: the node's two
/// triangles (diagonal from corner 00 to 11) over its corners `q` (00, 10,
/// 11, 01).
fn drawn(q: [Vec3; 4], x: f32, y: f32) -> Vec3 {
    let [q00, q10, q11, q01] = q;
    if x >= y {
        q00 + (q10 - q00) * x + (q11 - q10) * y
    } else {
        q00 + (q11 - q01) * x + (q01 - q00) * y
    }
}

/// Percentiles of the distance in pixels between the surface and what the
/// ready nodes draw at the same parameters (the parametric error, the
/// stricter of the criterion's two measures), over a 5×5 grid inside every
/// node: (p50, p99, max).
fn parametric_error(
    ready: &[bezier_subdiv::patch::quadnode::QuadNode],
    point: impl Fn(usize, f32, f32) -> Vec3,
    vp: &ViewParams,
    keep: impl Fn(usize) -> bool,
) -> (f32, f32, f32, usize) {
    let mut errs = Vec::new();
    for q in ready {
        let g = q.patch() as usize;
        if !keep(g) {
            continue;
        }
        let (a, b, c, d) = q.domain();
        let corners = [
            point(g, a, c),
            point(g, b, c),
            point(g, b, d),
            point(g, a, d),
        ];
        for i in 1..5 {
            for j in 1..5 {
                let (x, y) = (i as f32 / 5.0, j as f32 / 5.0);
                let s = point(g, a + (b - a) * x, c + (d - c) * y);
                let z = bezier_subdiv::patch::ops::affine_row(vp.depth_row, s).max(vp.near);
                errs.push((s - drawn(corners, x, y)).length() / (vp.eps_k * z));
            }
        }
    }
    errs.sort_by(f32::total_cmp);
    let at = |p: f64| errs[((errs.len() - 1) as f64 * p) as usize];
    (at(0.5), at(0.99), *errs.last().unwrap(), errs.len())
}

/// ε still holds on the displaced surface: the parametric error of what
/// the displaced nodes draw, in pixels, against the displaced surface
/// itself, is within what the criterion promises at λ = 0.5 (δp ≤ √2·ε
/// where the orthogonal distance is 0) at the 99th percentile, as for the
/// undisplaced surface.
#[test]
fn eps_holds_on_the_displaced_surface() {
    let (scene, geo) = displaced_scene();
    let dc = Displaced::of(&geo).unwrap();
    for vp in views(&scene, &geo) {
        let res = subdivide_displaced(&dc, &vp, 2);
        let plain = subdivide_parallel(&geo.patches, &geo.flags, &vp, 2);
        let disp = parametric_error(&res.ready, |g, u, v| dc.point(g, u, v), &vp, |_| true);
        let base = parametric_error(
            &plain.ready,
            |g, u, v| geo.patches[g].eval(u, v),
            &vp,
            |_| true,
        );
        println!(
            "aniso {}: displaced p50 {:.3} p99 {:.3} max {:.2} px ({} points); undisplaced p50 {:.3} p99 {:.3} max {:.2} px",
            vp.has(FLAG_ANISO),
            disp.0,
            disp.1,
            disp.2,
            disp.3,
            base.0,
            base.1,
            base.2
        );
        assert!(
            disp.1 <= std::f32::consts::SQRT_2,
            "displaced p99 {} px",
            disp.1
        );
    }
}

/// On the GPU (lavapipe, validation layer on): the subdivision kernels
/// displace exactly as the oracle does: the ready set of the displaced
/// criterion and every displaced vertex bit for bit, on the mesh and the
/// fallback draw paths, `iso` and `aniso`, persistent and per-depth
/// kernels. (The mesh is watertight on the CPU, above; equal bits carry
/// it over.)
#[test]
fn the_gpu_displaces_bit_for_bit_as_the_oracle() {
    use bezier_subdiv::commands::validate::{run, ValidateArgs};
    use bezier_subdiv::commands::GpuRequest;
    use bezier_subdiv::draw::DrawRequest;
    use bezier_subdiv::patch::view::Split;
    let _gpu = common::gpu();
    let cases = [
        ("subdiv", DrawRequest::Mesh, Split::Iso),
        ("subdiv", DrawRequest::Fallback, Split::Aniso),
        ("subdiv-indirect", DrawRequest::Mesh, Split::Aniso),
    ];
    for (method, draw, split) in cases {
        let mut gpu = GpuRequest::new(scene_path("displaced.toml"));
        gpu.size = (320, 180);
        gpu.draw = draw;
        gpu.validation = true;
        gpu.method = method.to_string();
        gpu.split = Some(split);
        let report = run(&ValidateArgs {
            gpu,
            frames: vec![0],
            skip_holes: true,
            debug_dir: None,
        })
        .unwrap();
        println!("{}", report.table);
        assert!(report.ok(), "{}", report.table);
        for check in ["ready set", "positions"] {
            let r = report.results.iter().find(|r| r.check == check);
            assert!(
                r.is_some_and(|r| r.ok),
                "{method}: {check}\n{}",
                report.table
            );
        }
    }
}

/// Every method displaces watertight against the displaced ground truth
/// (issue 40): on a small scene of UV seams, a mirrored instance and poles,
/// `tess` and `cudatess` put the same levels (factors) and the same
/// displaced vertices on both sides of every shared edge, bit for bit;
/// `subdiv` draws the oracle's ready set and vertices; and `tess` and
/// `subdiv` show no hole against the displaced ground truth, with pixels
/// checked in every model (and `subdiv` cracks where its wedges are off).
#[test]
fn the_methods_and_the_ground_truth_displace_watertight() {
    use bezier_subdiv::commands::validate::{run, ValidateArgs};
    use bezier_subdiv::commands::GpuRequest;
    let _gpu = common::gpu();
    let scene =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/displaced_seams.toml");
    let cases = [
        ("tess", &["edge levels", "edge vertices"][..], true),
        (
            "cudatess",
            &["edge factors", "largest factor", "edge vertices"][..],
            false,
        ),
        ("subdiv", &["ready set", "positions"][..], true),
    ];
    for (method, checks, holes) in cases {
        let mut gpu = GpuRequest::new(scene.clone());
        gpu.size = (256, 144);
        gpu.validation = true;
        gpu.method = method.to_string();
        let report = run(&ValidateArgs {
            gpu,
            frames: vec![0],
            skip_holes: !holes,
            debug_dir: None,
        })
        .unwrap();
        println!("{}", report.table);
        assert!(report.ok(), "{method}\n{}", report.table);
        let passed = |check: &str| report.results.iter().any(|r| r.check == check && r.ok);
        for check in checks {
            assert!(passed(check), "{method}: {check}\n{}", report.table);
        }
        if holes {
            let models = ["catmark_torus.obj", "catmark_cube.obj", "teapot.bpt"];
            for m in models {
                let name = format!("holes {m}");
                let r = report.results.iter().find(|r| r.check == name);
                assert!(
                    r.is_some_and(|r| r.ok),
                    "{method}: {name}\n{}",
                    report.table
                );
                if method == "subdiv" {
                    // "…; wedges off: N": the holes the same views show
                    // without wedges, which the test must be able to see.
                    let detail = &r.unwrap().detail;
                    let cracks: u64 = detail
                        .split("wedges off: ")
                        .nth(1)
                        .and_then(|t| t.split(|c: char| !c.is_ascii_digit()).next())
                        .and_then(|n| n.parse().ok())
                        .unwrap_or_else(|| panic!("{m}: no count without wedges: {detail}"));
                    assert!(cracks > 0, "{m}: no cracks without wedges: {detail}");
                }
            }
        }
    }
}

/// The window's displacement toggle (`FLAG_UNDISPLACED`): the displaced
/// scene drawn with the flag is, pixel for pixel, the scene without its
/// displacement; without the flag it is not.
#[test]
fn the_undisplaced_flag_draws_the_base_surfaces() {
    use bezier_subdiv::constants::{FLAG_UNDISPLACED, SHADE_NORMAL};
    use bezier_subdiv::draw::DrawPath;
    use bezier_subdiv::frame::View;
    use bezier_subdiv::methods::MethodOptions;
    use bezier_subdiv::scene::geometry::SceneGeometry;
    let gpu = common::gpu();
    let size = (320, 180);
    let (scene, geo) = common::scene("displaced.toml");
    let mut base = geo.clone();
    base.displacement = Default::default();
    let camera = scene.frame_camera(0).unwrap();
    let image = |g: &SceneGeometry, flags: u32| {
        let mut r = common::renderer(&gpu, g, "subdiv", size, MethodOptions::new(DrawPath::Mesh));
        let mut view = View::new(&camera, size, 1.0, 0.5, SHADE_NORMAL);
        view.params.flags |= flags;
        r.render(&view).unwrap();
        r.read_image().unwrap()
    };
    let differing = |a: &[u8], b: &[u8]| {
        a.chunks_exact(4)
            .zip(b.chunks_exact(4))
            .filter(|(p, q)| p != q)
            .count()
    };
    let plain = image(&base, 0);
    let toggled = image(&geo, FLAG_UNDISPLACED);
    let displaced = image(&geo, 0);
    assert_eq!(
        differing(&toggled, &plain),
        0,
        "the flag draws the base surfaces"
    );
    let moved = differing(&displaced, &plain);
    println!("displaced against base: {moved} pixels differ");
    assert!(moved > 5_000, "displacement shows ({moved} pixels)");
}

/// `--shade displacement` shows the maps' heights on displaced models
/// (from dark blue at 0 to yellow at 1: both low and high and much between on
/// scenes/displaced.toml, whose grout is 0 and bump tops 1) and grey on
/// a model that is not displaced (the teapot scene).
#[test]
fn the_displacement_view_shows_heights_where_models_are_displaced() {
    use bezier_subdiv::constants::SHADE_DISPLACEMENT;
    use bezier_subdiv::draw::DrawPath;
    use bezier_subdiv::frame::View;
    use bezier_subdiv::methods::MethodOptions;
    let gpu = common::gpu();
    let size = (320, 180);
    let image = |scene: &str| {
        let (scene, geo) = common::scene(scene);
        let mut r = common::renderer(
            &gpu,
            &geo,
            "subdiv",
            size,
            MethodOptions::new(DrawPath::Mesh),
        );
        let camera = scene.frame_camera(0).unwrap();
        r.render(&View::new(&camera, size, 1.0, 0.5, SHADE_DISPLACEMENT))
            .unwrap();
        r.read_image().unwrap()
    };
    let near = |p: &[u8], c: [f32; 3]| (0..3).all(|k| (p[k] as f32 - c[k] * 255.0).abs() <= 3.0);
    let (low, grey) = ([0.05, 0.10, 0.45], [0.35, 0.35, 0.35]);
    let displaced = image("displaced.toml");
    let px: Vec<&[u8]> = displaced.chunks_exact(4).collect();
    let lows = px.iter().filter(|p| near(p, low)).count();
    // Heights above 0.7: red above 0.7 of the way from dark blue to yellow.
    let highs = px.iter().filter(|p| p[0] > 190 && p[2] < 110).count();
    let colours: HashSet<&[u8]> = px.iter().copied().collect();
    println!(
        "displaced: {lows} low, {highs} high, {} colours",
        colours.len()
    );
    assert!(lows > 500 && highs > 500 && colours.len() > 200);
    let plain = image("teapot.toml");
    let background = plain[..4].to_vec();
    let model: Vec<&[u8]> = plain.chunks_exact(4).filter(|p| *p != background).collect();
    assert!(model.len() > 1000, "the teapot is in view");
    assert!(
        model.iter().all(|p| near(p, grey)),
        "an undisplaced model is grey"
    );
}
