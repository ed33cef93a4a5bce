//! Animation on the CPU (`src/anim/`): the deformers' pose is the import
//! of the deformed cage, OBJ sequences read their frames and refuse another
//! topology with the file and line, the scene keys are checked with
//! sentences, time wraps.

use std::path::{Path, PathBuf};

use bezier_subdiv::anim::{deform, AnimatedScene};
use bezier_subdiv::cage::obj;
use bezier_subdiv::scene::desc::Scene;
use glam::Vec3;

mod common;

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

fn demo() -> (Scene, AnimatedScene) {
    let scene = Scene::load(&scenes().join("anim.toml")).unwrap();
    let loaded = scene.load_animated().unwrap();
    (scene, loaded)
}

/// The demo's deformed torus (180° twist and a bend) and waving flag at
/// several times are, bit for bit, the import of their deformed cages
/// written out as OBJ: the same conversion either way.
#[test]
fn a_deformed_frame_is_the_import_of_the_deformed_cage() {
    let (scene, loaded) = demo();
    let anim = loaded.animation.as_ref().expect("the demo moves");
    assert_eq!(anim.models.len(), 2, "torus and flag deform");
    for t in [0.0, 0.7, 2.0, 3.3] {
        let frame = anim.frame(t);
        for (m, model) in anim.models.iter().enumerate() {
            let desc = &scene.models[model.scene_model];
            let verts = deform::apply_all(&frame.deformers[m], &model.cage.rest);
            let (patches, shading) = anim.model_pose(&frame, m);
            let text = std::fs::read_to_string(&desc.file).unwrap();
            let again = obj::parse_with(
                &desc.file,
                &common::cages::with_positions(&text, &model.cage, &verts),
                &desc.options,
            )
            .unwrap();
            assert_eq!(again.patches.len(), patches.len());
            for (k, (a, b)) in patches.iter().zip(&again.patches).enumerate() {
                assert_eq!(
                    a.pts.map(bits),
                    b.pts.map(bits),
                    "{} at t = {t}: patch {k}",
                    desc.name
                );
            }
            assert_eq!(shading, again.shading, "{} at t = {t}: shading", desc.name);
        }
    }
}

/// The oracle's scene at time t: the moving models' patches and the keyed
/// instances placed, everything else as loaded.
#[test]
fn the_scene_at_a_time_moves_only_what_moves() {
    let (scene, loaded) = demo();
    let anim = loaded.animation.as_ref().unwrap();
    let (rest, _) = loaded.at(0.0);
    let (moved, _) = loaded.at(1.3);
    let mut first = 0;
    for (index, m) in rest.models.iter().enumerate() {
        let n = m.patches_per_instance * m.instances;
        let range = first..first + n;
        first += n;
        let changed = rest.patches[range.clone()]
            .iter()
            .zip(&moved.patches[range])
            .filter(|(a, b)| a.pts.map(bits) != b.pts.map(bits))
            .count();
        let moves = scene.models[index].anim.moves();
        println!("{}: {changed} of {n} patches moved at t = 1.3", m.name);
        if moves {
            assert!(changed > 0, "{} should move", m.name);
        } else {
            assert_eq!(changed, 0, "{} should stand still", m.name);
        }
    }
    // One period later the loop is where it was.
    let (again, _) = loaded.at(1.3 + anim.duration);
    assert_eq!(
        moved
            .patches
            .iter()
            .map(|p| p.pts.map(bits))
            .collect::<Vec<_>>(),
        again
            .patches
            .iter()
            .map(|p| p.pts.map(bits))
            .collect::<Vec<_>>()
    );
    assert_eq!(anim.wrap(5.0), 1.0);
    assert_eq!(anim.frame(4.0 / anim.fps).time, 4.0 / 24.0);
}

/// A scene of one torus sequence in a scratch directory, frames `frames`
/// (each the torus cage with its vertices moved by `f(k, p)`).
fn sequence(tag: &str, frames: usize, f: &dyn Fn(usize, [f64; 3]) -> [f64; 3]) -> PathBuf {
    let dir = common::output_dir(&format!("anim-seq-{tag}"));
    for entry in std::fs::read_dir(&dir).unwrap() {
        std::fs::remove_file(entry.unwrap().path()).unwrap();
    }
    let torus = std::fs::read_to_string(scenes().join("models/catmark_torus.obj")).unwrap();
    for k in 0..frames {
        let mut out = String::new();
        for line in torus.lines() {
            let w: Vec<&str> = line.split_whitespace().collect();
            if w.first() == Some(&"v") {
                let p = [1, 2, 3].map(|i| w[i].parse::<f64>().unwrap());
                let q = f(k, p);
                out += &format!("v {:.6} {:.6} {:.6}\n", q[0], q[1], q[2]);
            } else {
                out += line;
                out.push('\n');
            }
        }
        std::fs::write(dir.join(format!("walk_{:04}.obj", k + 1)), out).unwrap();
    }
    let toml = "[camera]\nposition = [0.0, -6.0, 2.0]\ntarget = [0.0, 0.0, 0.0]\n\
                [animation]\nfps = 10.0\n[[model]]\nfile = \"walk_####.obj\"\n";
    std::fs::write(dir.join("scene.toml"), toml).unwrap();
    dir
}

/// An OBJ sequence: frame k at t = k / fps is the import of that frame's
/// file bit for bit, in between the vertices are interpolated.
#[test]
fn sequences_play_their_frames() {
    let grow = |k: usize, p: [f64; 3]| p.map(|c| c * (1.0 + 0.1 * k as f64));
    let dir = sequence("play", 3, &grow);
    let scene = Scene::load(&dir.join("scene.toml")).unwrap();
    assert_eq!(scene.models[0].anim.sequence.len(), 3);
    let loaded = scene.load_animated().unwrap();
    let anim = loaded.animation.as_ref().unwrap();
    assert!((anim.duration - 0.3).abs() < 1e-12, "{}", anim.duration);
    for k in 0..3 {
        let frame = anim.frame(k as f64 / anim.fps);
        let (patches, _) = anim.model_pose(&frame, 0);
        let file = dir.join(format!("walk_{:04}.obj", k + 1));
        let own = obj::read(&file).unwrap();
        for (a, b) in patches.iter().zip(&own.patches) {
            assert_eq!(a.pts.map(bits), b.pts.map(bits), "frame {k}");
        }
    }
    // Halfway between frames 0 and 1: the vertices halfway.
    let frame = anim.frame(0.05);
    let v0 = anim.models[0].cage.rest[0];
    let want = v0 + (v0 * 1.1 - v0) * 0.5;
    assert!((frame.inputs[0][0] - want).length() < 1e-6);
}

/// A sequence scene named by a bare file name, from its own directory
/// (issue 35: "error: : No such file or directory", the frames looked up
/// in the directory "").
#[test]
fn a_sequence_scene_loads_by_its_bare_name() {
    let dir = sequence("bare", 2, &|_, p| p);
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_bezier-subdiv"))
        .args(["stats", "--scene", "scene.toml", "--size", "64x36"])
        .current_dir(&dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{err}");
}

/// A frame with another topology is refused with its file and line; a
/// missing frame with its file name.
#[test]
fn sequences_refuse_another_topology_and_gaps() {
    let dir = sequence("bad", 3, &|_, p| p);
    let bad = dir.join("walk_0002.obj");
    let text = std::fs::read_to_string(&bad).unwrap();
    let first_f = text.lines().position(|l| l.starts_with("f ")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    lines[first_f] = "f 1 2 3 4".into();
    std::fs::write(&bad, lines.join("\n") + "\n").unwrap();
    let scene = Scene::load(&dir.join("scene.toml")).unwrap();
    let e = scene.load_animated().unwrap_err().to_string();
    assert!(
        e.contains(&format!("walk_0002.obj:{}", first_f + 1))
            && e.contains("differs from the first frame's"),
        "{e}"
    );
    std::fs::remove_file(&bad).unwrap();
    let e = Scene::load(&dir.join("scene.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("walk_0002.obj") && e.contains("missing"), "{e}");
}

/// Scene keys that cannot be meant are refused with a sentence naming the
/// model and what is wrong.
#[test]
fn bad_animation_keys_are_explained() {
    let base = "[camera]\nposition = [0.0, -6.0, 2.0]\ntarget = [0.0, 0.0, 0.0]\n\
                [[model]]\nname = \"t\"\nfile = \"models/catmark_torus.obj\"\n";
    let parse = |extra: &str| {
        Scene::parse(&scenes().join("x.toml"), &format!("{base}{extra}"))
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let e = parse("[[model.deform]]\nkind = \"bend\"\nangle_deg = 30.0\nlength = 1.0\n");
    assert!(e.contains("model 't'") && e.contains("toward"), "{e}");
    let e = parse("[[model.deform]]\nkind = \"twist\"\nangle_deg = [[1.0, 0.0], [0.5, 2.0]]\n");
    assert!(e.contains("key times must increase"), "{e}");
    let e = parse("[[model.deform]]\nkind = \"twist\"\nangle_deg = 1.0\namplitude = 2.0\n");
    assert!(e.contains("`amplitude` does not apply"), "{e}");
    let e = parse("[[model.deform]]\nkind = \"spin\"\n");
    assert!(e.contains("x.toml:") && e.contains("spin"), "{e}");
    let e = parse(
        "[[model.instance]]\n[[model.instance.key]]\ntime = 0.0\nscale = 1.0\n\
         [[model.instance.key]]\ntime = 1.0\nscale = [-1.0, 1.0, 1.0]\n",
    );
    assert!(e.contains("instance 1") && e.contains("mirror"), "{e}");
    let e = Scene::parse(
        &scenes().join("x.toml"),
        &base.replace("catmark_torus.obj", "no_such_####.obj"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no frame files match"), "{e}");
    let e = Scene::parse(
        &scenes().join("x.toml"),
        &format!(
            "{}[[model.deform]]\nkind = \"twist\"\nangle_deg = 1.0\n",
            base.replace("catmark_torus.obj", "rational_torus.rbpt")
        ),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("rational"), "{e}");
}

/// A scene without motion has no animation, and its geometry is the
/// static one.
#[test]
fn a_static_scene_has_no_animation() {
    let scene = Scene::load(&scenes().join("teapot.toml")).unwrap();
    let loaded = scene.load_animated().unwrap();
    assert!(loaded.animation.is_none());
    let (geo, _) = scene.geometry_and_shading().unwrap();
    assert_eq!(
        loaded
            .geometry
            .patches
            .iter()
            .map(|p| p.pts.map(bits))
            .collect::<Vec<_>>(),
        geo.patches
            .iter()
            .map(|p| p.pts.map(bits))
            .collect::<Vec<_>>()
    );
    let _ = Path::new("");
}
