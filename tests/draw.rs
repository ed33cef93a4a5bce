//! Both draw paths on a real device (lavapipe in CI), validation on, fed a
//! ready list the CPU oracle made (so no subdivision kernel is involved):
//! vertex positions equal the oracle's bit for bit, the two paths' images
//! agree, wedges switch off as expected, and the winding makes outward
//! faces front faces. Images of failures go to Cargo's scratch directory
//! (`CARGO_TARGET_TMPDIR`), `draw/`.

mod common;
mod draw_rig;

use ash::vk;
use glam::DVec3;

use bezier_subdiv::constants::*;
use bezier_subdiv::draw::{choose, choose_for, indirect_args, DrawPath, DrawRequest};
use bezier_subdiv::gpu::DrawTarget;
use bezier_subdiv::patch::oracle::triangle_counts;
use bezier_subdiv::patch::view::FLAG_BACKFACE_CULL;
use bezier_subdiv::scene::camera::Camera;
use bezier_subdiv::scene::desc::Scene;
use bezier_subdiv::vk::VkError;

use draw_rig::*;

#[test]
fn choose_follows_the_device() {
    let ctx = common::gpu();
    let mut info = ctx.info().clone();
    let has_mesh = info.has_mesh_shader();
    assert_eq!(
        choose(&ctx, DrawRequest::Auto).unwrap(),
        if has_mesh {
            DrawPath::Mesh
        } else {
            DrawPath::Fallback
        }
    );
    assert_eq!(
        choose(&ctx, DrawRequest::Fallback).unwrap(),
        DrawPath::Fallback
    );
    // The same device without mesh shaders.
    info.features.mesh_shader = false;
    info.mesh = None;
    assert_eq!(
        choose_for(&info, DrawRequest::Auto).unwrap(),
        DrawPath::Fallback
    );
    let err = choose_for(&info, DrawRequest::Mesh).unwrap_err();
    assert!(matches!(err, VkError::FeatureMissing { .. }), "{err}");
    let msg = err.to_string();
    assert!(
        msg.contains("VK_EXT_mesh_shader") && msg.contains("fallback"),
        "{msg}"
    );
    println!("forcing mesh without mesh shaders: {msg}");
    for (s, r) in [
        ("auto", DrawRequest::Auto),
        ("Mesh", DrawRequest::Mesh),
        ("fallback", DrawRequest::Fallback),
    ] {
        assert_eq!(s.parse::<DrawRequest>().unwrap(), r);
    }
    assert!("tess".parse::<DrawRequest>().is_err());
    ctx.finish();
}

/// The fallback's chunks split any list the ready list can hold into
/// consecutive runs of at most FALLBACK_CHUNK_NODES nodes, in order, and
/// each chunk's expansion covers exactly the nodes its draw draws.
#[test]
fn fallback_chunks_cover_the_list_once() {
    let max = FALLBACK_CHUNK_NODES * FALLBACK_MAX_CHUNKS;
    for ready in [
        0,
        1,
        63,
        FALLBACK_CHUNK_NODES,
        FALLBACK_CHUNK_NODES + 1,
        1_008_402,
        max,
    ] {
        let mut words = vec![0u32; COUNTERS_BUFFER_WORDS as usize];
        for (word, value) in indirect_args(ready) {
            words[word as usize] = value;
        }
        let mut left = ready;
        for c in 0..FALLBACK_MAX_CHUNKS {
            let a = (C_CHUNK_ARGS + CHUNK_ARG_WORDS * c) as usize;
            let nodes = left.min(FALLBACK_CHUNK_NODES);
            left -= nodes;
            let expand = nodes.div_ceil(EXPAND_GROUP_SIZE);
            assert_eq!(
                words[a..a + 8],
                [expand, 1, 1, 0, nodes * VERTICES_PER_NODE, 1, 0, 0]
            );
        }
        assert_eq!(left, 0, "{ready} nodes: the chunks hold {}", ready - left);
    }
}

/// Positions bit for bit against the oracle on both paths, and the two
/// paths' images against each other, for the teapot (scene camera and a
/// close-up of the spout) and the converted torus and cube, in all three
/// viewing modes on the teapot.
#[test]
fn paths_match_the_oracle_and_each_other() {
    let ctx = common::gpu();
    let mut rig = Rig::new(&ctx);
    let cases = [
        teapot(0, "teapot"),
        teapot(1, "teapot-spout"),
        converted("catmark_torus.obj", 1),
        converted("catmark_cube.obj", 2),
    ];
    for case in &cases {
        let shades: &[u32] = if case.name.starts_with("teapot") {
            &[SHADE_NORMAL, SHADE_DEPTH, SHADE_WEDGES]
        } else {
            &[SHADE_NORMAL]
        };
        for &shade in shades {
            both_paths(&mut rig, case, shade);
        }
    }
    // The close-up must subdivide deeper than the overview, or the depth
    // images show nothing.
    let deepest = |c: &Case| c.ready.iter().map(|q| q.depth()).max().unwrap();
    assert!(deepest(&cases[1]) > deepest(&cases[0]));
    ctx.finish();
}

/// Under 1:2 splits a node has a depth per direction and a wedge on any of
/// its four edges: both paths still draw the oracle's vertices bit for bit
/// (the fallback's slots, the mesh path's capture) and agree on the image.
/// The teapot's spout, the torus (curved more around the tube than along)
/// and the four-patch tube (straight along its axis) all split 1:2.
#[test]
fn aniso_nodes_draw_the_oracle_s_vertices_on_both_paths() {
    let ctx = common::gpu();
    let mut rig = Rig::new(&ctx);
    let tube = {
        let scene = Scene::load(&root().join("scenes/cylinder.toml")).expect("cylinder scene");
        let geo = scene.geometry().expect("cylinder geometry");
        let cam = scene.frame_camera(0).unwrap();
        Case::new("tube", geo.patches, geo.flags, cam, 0)
    };
    let cases = [
        teapot(1, "teapot-spout").aniso("teapot-spout-aniso"),
        converted("catmark_torus.obj", 1).aniso("torus-aniso"),
        tube.aniso("tube-aniso"),
    ];
    for case in &cases {
        let halved = case.ready.iter().filter(|q| q.du() != q.dv()).count();
        let (_, wedges) = triangle_counts(&case.ready, true);
        println!(
            "{}: {} ready nodes, {halved} with unequal depths, {wedges} wedges",
            case.name,
            case.ready.len()
        );
        assert!(
            halved > 0,
            "{}: no 1:2 node, the test proves nothing",
            case.name
        );
        for shade in [SHADE_NORMAL, SHADE_WEDGES] {
            both_paths(&mut rig, case, shade);
        }
    }
    ctx.finish();
}

/// Clearing FLAG_WEDGES in the view drops exactly the wedge triangles on
/// both paths (the ready list staying the same).
#[test]
fn wedges_off_drops_the_wedges() {
    let ctx = common::gpu();
    let mut rig = Rig::new(&ctx);
    for base in [teapot(1, "teapot-spout"), converted("catmark_torus.obj", 1)] {
        let (with_tris, with_wedges) = triangle_counts(&base.ready, true);
        let n = base.ready.len();
        assert!(
            with_wedges > 0,
            "{}: no wedges, the test proves nothing",
            base.name
        );
        let off = base.with_flags(
            &format!("{}-nowedges", base.name),
            base.vp.flags & !FLAG_WEDGES,
        );
        let mut images = Vec::new();
        for case in [&base, &off] {
            let [mesh, fallback] = both_paths(&mut rig, case, SHADE_WEDGES);
            // Triangle slots whose three vertices are not one repeated vertex.
            let vw = VERTEX_WORDS as usize;
            let drawn = fallback.vertices[..n * VERTICES_PER_NODE as usize * vw]
                .chunks_exact(3 * vw)
                .filter(|t| t[..vw] != t[vw..2 * vw] || t[..vw] != t[2 * vw..])
                .count();
            // Wedge pivots the mesh path evaluated (the capture marks them).
            let pivots = (0..n)
                .flat_map(|i| (4..8).map(move |s| NODE_MESH_SLOTS as usize * i + s))
                .filter(|&v| mesh.capture[4 * v] != SENTINEL)
                .count();
            let (tris, wedges) = if case.wedges() {
                (with_tris as usize, with_wedges as usize)
            } else {
                (2 * n, 0)
            };
            println!(
                "{}: {n} nodes: fallback draws {drawn} triangles (expected {tris}), \
                 mesh evaluates {pivots} wedge pivots (expected {wedges})",
                case.name
            );
            assert_eq!(drawn, tris, "{}", case.name);
            assert_eq!(pivots, wedges, "{}", case.name);
            images.push(mesh.rgba);
        }
        let (changed, img) = diff(&images[0], &images[1]);
        save(&format!("{}-wedges-on-vs-off", base.name), &img);
        println!("{}: wedges off changes {changed} pixels", base.name);
        assert!(changed > 0, "{}: the wedges were invisible", base.name);
    }
    ctx.finish();
}

/// SHADE_FACING: a closed model with outward normals (checked on the CPU)
/// shows front faces (white) from outside and back faces (green) from inside,
/// with no background inside the outline, except on folded wedges: the
/// front-face setting matches the triangles' winding and there are no holes.
#[test]
fn key_shading_shows_the_winding() {
    let ctx = common::gpu();
    let mut rig = Rig::new(&ctx);
    let (patches, flags) = model("catmark_cube.obj", 0);
    let (c, r) = bounds(&patches);
    // From the centre of the (convex) cube every visible point is the inside.
    let camera = Camera {
        position: c.to_array(),
        target: (c + DVec3::new(1.0, 0.3, 0.2)).to_array(),
        up: [0.0, 0.0, 1.0],
        fov_y_deg: 100.0,
        near: 0.001 * r,
        far: 10.0 * r,
    };
    let inside = Case::new("cube-inside", patches, flags, camera, FLAG_BACKFACE_CULL);
    let views = [
        (converted("catmark_cube.obj", 0), true),
        (converted("catmark_torus.obj", 0), true),
        (inside, false),
    ];
    for (case, outside) in &views {
        let volume = signed_volume(case);
        assert!(
            volume > 0.0,
            "{}: normals point inward ({volume})",
            case.name
        );
        let wedges = both_paths(&mut rig, case, SHADE_WEDGES);
        let keys = both_paths(&mut rig, case, SHADE_FACING);
        for (k, w) in keys.iter().zip(&wedges) {
            let (white, green) = (count_pixels(&k.rgba, WHITE), count_pixels(&k.rgba, GREEN));
            let bg = count_pixels(&k.rgba, BG_RGBA);
            let wrong = unexplained(&k.rgba, &w.rgba, if *outside { GREEN } else { WHITE });
            println!(
                "{}: {white} white, {green} green, {bg} background; \
                 wrong side off wedges and silhouettes: {wrong:?}",
                case.name
            );
            assert!(wrong.is_empty(), "{}: wrong faces seen", case.name);
            assert_eq!(
                white + green + bg,
                (W * H) as usize,
                "{}: other colours",
                case.name
            );
            if *outside {
                assert!(white > 1000, "{}: no front faces", case.name);
            } else {
                assert_eq!(bg, 0, "{}: holes", case.name);
            }
        }
    }
    ctx.finish();
}

/// Timer scopes, and misuse reported as an error rather than as an
/// out-of-bounds shader access, with nothing submitted.
#[test]
fn timer_scopes_and_misuse() {
    let ctx = common::gpu();
    let mut rig = Rig::new(&ctx);
    let case = converted("catmark_cube.obj", 2);
    let scene = rig.scene(&case);
    for path in PATHS {
        let _ = render(&mut rig, &case, &scene, path, SHADE_NORMAL);
        let scopes = rig.timer.read().unwrap();
        println!("{path}: {scopes:?}");
        let names: Vec<&str> = scopes.iter().map(|(n, _)| n.as_str()).collect();
        match path {
            DrawPath::Mesh => assert_eq!(names, ["draw"]),
            DrawPath::Fallback => assert_eq!(names, ["expand", "draw"]),
        }
    }
    // A capture asked of a list without a capture buffer.
    let mut retired = bezier_subdiv::frame::Retired::default();
    let stage = rig.stage(DrawPath::Mesh);
    stage.ensure_capture(&ctx, false, &mut retired).unwrap();
    let before = rig.target.read_rgba(&ctx).unwrap();
    let err = rig
        .draw(&scene, &case_view(&case, SHADE_DEPTH), DrawPath::Mesh, true)
        .unwrap_err();
    assert!(err.to_string().contains("capture"), "{err}");
    // The failed recording was not submitted: the image is unchanged.
    assert_eq!(rig.target.read_rgba(&ctx).unwrap(), before);
    ctx.finish();
}

/// The draw target rejects readback before anything was drawn.
#[test]
fn target_readback_needs_a_draw() {
    let ctx = common::gpu();
    let target = DrawTarget::new(&ctx, 8, 8, BG).unwrap();
    assert!(target.read_rgba(&ctx).is_err());
    assert_eq!(target.color().format(), vk::Format::R8G8B8A8_UNORM);
    ctx.finish();
}
