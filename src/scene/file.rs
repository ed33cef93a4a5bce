//! Scene files (TOML): models with instance transforms, a camera, an optional
//! camera path and camera orbit, and default ε and λ.
//!
//! ```toml
//! name = "teapot"
//! [view]                      # optional defaults for render/bench
//! eps = 1.0                   # pixel tolerance ε
//! lambda = 0.5                # orthogonal (0) ↔ parametric (1) distance
//! [camera]
//! position = [6.0, -6.5, 4.0]
//! target = [0.0, 0.0, 1.2]
//! up = [0.0, 0.0, 1.0]        # default +z
//! fov_y_deg = 45.0            # default 45
//! near = 0.05                 # default 0.05
//! far = 1000.0                # default 1000
//! [camera_path]               # optional; frame 0 is [camera], frame k is key k
//! frames = 240                # frames `bench` samples along the path
//! [[camera_path.key]]
//! position = [...]
//! target = [...]
//! [camera_orbit]              # optional; the path `bench` samples (else the
//!                             # keys above, else an orbit of the bounding box)
//! center = [0.0, 0.0, 1.2]    # looked at, circled about `up`
//! distance = [3.0, 12.0]      # eye distance from the axis: nearest, farthest
//! height = [0.5, 4.0]         # eye above center when nearest, when farthest
//! turns = 1.0                 # revolutions over the path (default 1)
//! waves = 2.0                 # far → near → far cycles (default 2)
//! start_deg = 0.0             # azimuth of the first frame (from the x axis)
//! frames = 240                # frames `bench` samples (default 240)
//! # up, fov_y_deg, near, far: as in [camera]
//! [[model]]
//! name = "teapot"
//! file = "models/teapot.bpt"  # .bpt, rational .rbpt (weights per point;
//!                             # drawn by every method but tess and
//!                             # tess-reparam) or .obj, relative to this file
//! surface = "pn-triangles"    # .obj only: the mesh's triangles as PN triangles
//!                             # (quads, n-gons fanned; drawn by cudatess and
//!                             # ground-truth); default "cage" (Catmull–Clark)
//! two_sided = true            # open or thin models: never back-face culled
//! boundary = "edge-only"      # cages without a `t interpolateboundary` tag:
//!                             # none | edge-only | edge-and-corner (default)
//! isolate = 2                 # cages: Catmull–Clark steps before conversion
//!                             # where the patches would approximate the
//!                             # limit surface (0..6, default 0; see
//!                             # src/cage/isolate.rs)
//! fvar = "all"                # cages with texture coordinates: how they are
//!                             # interpolated, corners-only (default) | all
//!                             # (src/cage/uv.rs)
//! texture = "textures/a.png"  # albedo map (PNG, sRGB), in place of the one
//!                             # the OBJ's material (`map_Kd`) names; mapped
//!                             # by the cage's UVs, else each patch's (u, v)
//! displacement = { map = "textures/h.png", scale = 0.05, bias = 0.0 }
//!                             # height map (PNG, grey, power-of-two sides):
//!                             # the surface moves bias + scale·h along its
//!                             # unit normal, h in [0, 1] (src/scene/displacement.rs)
//! [[model.instance]]          # none given: one instance, identity
//! translate = [0.0, 0.0, 0.0]
//! rotate_deg = [0.0, 0.0, 0.0]  # about x, then y, then z
//! scale = 1.0                 # or [sx, sy, sz]
//! grid = { count = [4, 2, 1], step = [1.0, 1.0, 0.0] }  # optional lattice of copies
//! ```
//!
//! Instances are baked into world-space base patches at load (the transform
//! is applied to the control points in f64 and rounded once), so shared
//! boundary points stay bitwise shared within each instance. A mirroring
//! transform swaps each patch's u and v to keep normals outward.
//!
//! The scene they describe is [`Scene`] (`desc.rs`); this file reads it.
//!
//! A scene may ask for at most [`MAX_BASE_PATCHES`] base patches (what the
//! subdivision kernel's in-flight counter holds); more is refused before
//! anything is built, with the count and the memory it would need.

use std::path::Path;

use glam::{DMat4, DVec3, EulerRot};
use serde::Deserialize;

use super::camera::Camera;
use super::desc::{ModelAnim, ModelDesc, Scene, Surface, ViewDefaults};
use super::displacement::DisplacementDesc;
use super::orbit::Orbit;
use crate::cage::obj::CageOptions;
use crate::cage::sharpness::BoundaryRule;
use crate::cage::uv::FvarRule;
use crate::figures::{bytes_text, thousands};
use crate::input::limits::{GEOMETRY_BYTES_PER_PATCH, MAX_BASE_PATCHES};
use crate::input::SceneError;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneToml {
    name: Option<String>,
    #[serde(default)]
    view: ViewDefaults,
    camera: Camera,
    camera_path: Option<PathToml>,
    camera_orbit: Option<Orbit>,
    animation: Option<crate::scene::keys::AnimationToml>,
    #[serde(default)]
    model: Vec<ModelToml>,
}

fn default_frames() -> u32 {
    240
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PathToml {
    #[serde(default = "default_frames")]
    frames: u32,
    #[serde(default)]
    key: Vec<Camera>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelToml {
    name: Option<String>,
    file: String,
    #[serde(default)]
    two_sided: bool,
    boundary: Option<BoundaryRule>,
    #[serde(default)]
    isolate: u32,
    #[serde(default)]
    fvar: FvarRule,
    #[serde(default)]
    surface: Surface,
    texture: Option<String>,
    displacement: Option<DisplacementToml>,
    #[serde(default)]
    instance: Vec<InstanceToml>,
    #[serde(default)]
    deform: Vec<crate::scene::keys::DeformToml>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DisplacementToml {
    map: String,
    scale: f32,
    #[serde(default)]
    bias: f32,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct InstanceToml {
    #[serde(default)]
    translate: [f64; 3],
    #[serde(default)]
    rotate_deg: [f64; 3],
    #[serde(default)]
    scale: Scale,
    grid: Option<GridToml>,
    #[serde(default)]
    key: Vec<crate::scene::keys::KeyToml>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum Scale {
    Uniform(f64),
    PerAxis([f64; 3]),
}

impl Default for Scale {
    fn default() -> Self {
        Scale::Uniform(1.0)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GridToml {
    count: [u32; 3],
    step: [f64; 3],
}

fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

impl Scene {
    /// Reads and checks a scene file (models are loaded by [`Scene::geometry`]).
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = crate::input::text::read_text(path)?;
        Self::parse(path, &text)
    }

    /// Parses scene text; `path` names the file in errors and anchors
    /// relative model paths.
    pub fn parse(path: &Path, text: &str) -> Result<Scene, SceneError> {
        let raw: SceneToml = toml::from_str(text).map_err(|e| SceneError::Parse {
            path: path.to_path_buf(),
            line: e.span().map_or(1, |s| line_of(text, s.start)),
            msg: e.message().trim().to_string(),
        })?;
        let (keys, path_frames) = check_cameras(
            path,
            &raw.camera,
            raw.camera_path,
            raw.camera_orbit.as_ref(),
        )?;
        let v = raw.view;
        check_view(path, &v)?;
        if raw.model.is_empty() {
            return Err(SceneError::invalid(path, "the scene has no [[model]]"));
        }
        let dir = path.parent().unwrap_or(Path::new("."));
        let mut models = Vec::new();
        let mut instances_so_far = 0u64;
        for (i, m) in raw.model.iter().enumerate() {
            models.push(model_desc(path, dir, i, m, &mut instances_so_far)?);
        }
        let name = raw.name.unwrap_or_else(|| {
            path.file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        });
        Ok(Scene {
            path: path.to_path_buf(),
            name,
            view: v,
            camera: raw.camera,
            keys,
            path_frames,
            orbit: raw.camera_orbit,
            models,
            animation: raw.animation.unwrap_or_default(),
        })
    }
}

/// Checks `[camera]`, the camera path's keys and `[camera_orbit]`; returns
/// the path's keys and frames (none and the default without a path).
fn check_cameras(
    path: &Path,
    camera: &Camera,
    camera_path: Option<PathToml>,
    orbit: Option<&Orbit>,
) -> Result<(Vec<Camera>, u32), SceneError> {
    let invalid = |msg: String| SceneError::invalid(path, msg);
    camera
        .check()
        .map_err(|m| invalid(format!("[camera]: {m}")))?;
    let (keys, path_frames) = match camera_path {
        Some(p) => (p.key, p.frames),
        None => (Vec::new(), default_frames()),
    };
    for (k, key) in keys.iter().enumerate() {
        key.check()
            .map_err(|m| invalid(format!("camera_path key {} (frame {}): {m}", k + 1, k + 1)))?;
    }
    if let Some(o) = orbit {
        o.check()
            .map_err(|m| invalid(format!("[camera_orbit]: {m}")))?;
    }
    Ok((keys, path_frames))
}

/// Checks the `[view]` defaults: ε > 0 and λ in [0, 1].
fn check_view(path: &Path, v: &ViewDefaults) -> Result<(), SceneError> {
    let invalid = |msg: String| SceneError::invalid(path, msg);
    if !(v.eps.is_finite() && v.eps > 0.0) {
        return Err(invalid(format!("[view] eps must be > 0 (got {})", v.eps)));
    }
    if !(0.0..=1.0).contains(&v.lambda) {
        return Err(invalid(format!(
            "[view] lambda must be in [0, 1] (got {})",
            v.lambda
        )));
    }
    Ok(())
}

/// Model `i` of the scene, checked, its file resolved against `dir`;
/// `instances_so_far` counts the instances of the models up to it, which
/// are refused past [`MAX_BASE_PATCHES`] before any is built.
fn model_desc(
    path: &Path,
    dir: &Path,
    i: usize,
    m: &ModelToml,
    instances_so_far: &mut u64,
) -> Result<ModelDesc, SceneError> {
    let invalid = |msg: String| SceneError::invalid(path, msg);
    let name = m.name.clone().unwrap_or_else(|| format!("model {}", i + 1));
    if m.isolate > crate::cage::isolate::MAX_ISOLATE {
        return Err(invalid(format!(
            "model '{name}': isolate = {} is more than {}: each step quarters every face of the refined parts",
            m.isolate,
            crate::cage::isolate::MAX_ISOLATE
        )));
    }
    // Count before building: a grid of 10^10 copies must be refused,
    // not allocated. Every instance has at least one patch.
    let count =
        instance_count(&m.instance).map_err(|msg| invalid(format!("model '{name}': {msg}")))?;
    *instances_so_far = instances_so_far.saturating_add(count);
    let instances_so_far = *instances_so_far;
    if instances_so_far > MAX_BASE_PATCHES {
        return Err(invalid(format!(
            "model '{name}': {} instances{}: at one patch each that is already {} base patches \
             and at least {} of patch memory; a scene may have at most {} base patches",
            thousands(count),
            if instances_so_far > count {
                " (with the models before it)"
            } else {
                ""
            },
            thousands(instances_so_far),
            bytes_text(instances_so_far.saturating_mul(GEOMETRY_BYTES_PER_PATCH)),
            thousands(MAX_BASE_PATCHES),
        )));
    }
    let instances = instance_transforms(&m.instance)
        .map_err(|msg| invalid(format!("model '{name}': {msg}")))?;
    let anim = model_anim(m, dir).map_err(|e| match e {
        Err(msg) => invalid(format!("model '{name}': {msg}")),
        Ok(e) => e,
    })?;
    let file = anim
        .sequence
        .first()
        .cloned()
        .unwrap_or_else(|| dir.join(&m.file));
    let displacement =
        model_displacement(m, dir).map_err(|msg| invalid(format!("model '{name}': {msg}")))?;
    Ok(ModelDesc {
        name,
        file,
        two_sided: m.two_sided,
        options: CageOptions {
            boundary: m.boundary,
            isolate: m.isolate,
            fvar: m.fvar,
        },
        surface: m.surface,
        texture: m.texture.as_ref().map(|t| dir.join(t)),
        displacement,
        instances,
        anim,
    })
}

/// The model's `displacement` table, checked: finite scale and bias, a
/// surface that can carry it.
fn model_displacement(m: &ModelToml, dir: &Path) -> Result<Option<DisplacementDesc>, String> {
    let Some(d) = &m.displacement else {
        return Ok(None);
    };
    if !d.scale.is_finite() || !d.bias.is_finite() {
        return Err(format!(
            "displacement scale {} and bias {} must be finite",
            d.scale, d.bias
        ));
    }
    if m.surface == Surface::PnTriangles {
        return Err("displacement needs a patch surface, not PN triangles".to_string());
    }
    Ok(Some(DisplacementDesc {
        map: dir.join(&d.map),
        scale: d.scale,
        bias: d.bias,
    }))
}

/// The model's deformers, sequence and instance keys, checked; an error is
/// a sentence about the model (`Err`) or one about a file (`Ok`).
fn model_anim(m: &ModelToml, dir: &Path) -> Result<ModelAnim, Result<SceneError, String>> {
    let here = Err;
    let mut anim = ModelAnim::default();
    for (k, d) in m.deform.iter().enumerate() {
        anim.deform.push(
            d.check()
                .map_err(|e| here(format!("deform {}: {e}", k + 1)))?,
        );
    }
    if m.file.contains('#') {
        anim.sequence = super::sequence::frames(&dir.join(&m.file)).map_err(Ok)?;
    }
    for (k, inst) in m.instance.iter().enumerate() {
        let keys = if inst.key.is_empty() {
            None
        } else {
            Some(
                crate::scene::keys::InstanceKeys::new(&inst.key)
                    .map_err(|e| here(format!("instance {}: {e}", k + 1)))?,
            )
        };
        let count = match &inst.grid {
            Some(g) => g.count.iter().map(|&c| c as usize).product(),
            None => 1,
        };
        let step = inst
            .grid
            .as_ref()
            .map_or(DVec3::ZERO, |g| DVec3::from_array(g.step));
        let count3 = inst.grid.as_ref().map_or([1, 1, 1], |g| g.count);
        let mut offsets = Vec::with_capacity(count);
        for z in 0..count3[2] {
            for y in 0..count3[1] {
                for x in 0..count3[0] {
                    offsets.push(step * DVec3::new(x as f64, y as f64, z as f64));
                }
            }
        }
        for off in offsets {
            anim.keys.push(keys.as_ref().map(|k| k.offset(off)));
        }
    }
    if m.instance.is_empty() {
        anim.keys.push(None);
    }
    if anim.moves() && (m.surface == Surface::PnTriangles || m.file.ends_with(".rbpt")) {
        return Err(here(
            "only bicubic polynomial models (.obj cages, .bpt) can be animated: PN triangles and rational patches cannot".into(),
        ));
    }
    Ok(anim)
}

/// Number of instances `list` makes, or what is wrong with it.
fn instance_count(list: &[InstanceToml]) -> Result<u64, String> {
    if list.is_empty() {
        return Ok(1);
    }
    let mut total = 0u64;
    for (k, inst) in list.iter().enumerate() {
        let n = match &inst.grid {
            Some(g) => {
                if g.count.contains(&0) {
                    return Err(format!(
                        "instance {}: grid count must be ≥ 1 on every axis",
                        k + 1
                    ));
                }
                g.count.iter().map(|&c| c as u64).product()
            }
            None => 1,
        };
        total = total.saturating_add(n);
    }
    Ok(total)
}

fn instance_transforms(list: &[InstanceToml]) -> Result<Vec<DMat4>, String> {
    if list.is_empty() {
        return Ok(vec![DMat4::IDENTITY]);
    }
    let mut out = Vec::new();
    for (k, inst) in list.iter().enumerate() {
        let scale = match inst.scale {
            Scale::Uniform(s) => DVec3::splat(s),
            Scale::PerAxis(s) => DVec3::from_array(s),
        };
        if scale.x * scale.y * scale.z == 0.0 || !scale.is_finite() {
            return Err(format!(
                "instance {}: scale must be finite and non-zero",
                k + 1
            ));
        }
        let r = inst.rotate_deg.map(f64::to_radians);
        let base = DMat4::from_translation(DVec3::from_array(inst.translate))
            * DMat4::from_euler(EulerRot::ZYX, r[2], r[1], r[0])
            * DMat4::from_scale(scale);
        let (count, step) = match &inst.grid {
            Some(g) => (g.count, DVec3::from_array(g.step)),
            None => ([1, 1, 1], DVec3::ZERO),
        };
        if count.contains(&0) {
            return Err(format!(
                "instance {}: grid count must be ≥ 1 on every axis",
                k + 1
            ));
        }
        for z in 0..count[2] {
            for y in 0..count[1] {
                for x in 0..count[0] {
                    let off = step * DVec3::new(x as f64, y as f64, z as f64);
                    out.push(DMat4::from_translation(off) * base);
                }
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = r#"
[camera]
position = [5.0, -5.0, 3.0]
target = [0.0, 0.0, 1.0]

[[model]]
file = "teapot.bpt"
"#;

    fn parse(text: &str) -> Result<Scene, SceneError> {
        Scene::parse(Path::new("/tmp/x/scene.toml"), text)
    }

    #[test]
    fn minimal_scene_has_defaults() {
        let s = parse(MINIMAL).unwrap();
        assert_eq!(s.name, "scene");
        assert_eq!((s.view.eps, s.view.lambda), (1.0, 0.5));
        assert_eq!(s.frame_count(), 1);
        assert_eq!(s.models[0].file, Path::new("/tmp/x/teapot.bpt"));
        assert_eq!(s.models[0].instances, vec![DMat4::IDENTITY]);
    }

    #[test]
    fn unknown_keys_and_wrong_types_name_the_line() {
        let e = parse(&MINIMAL.replace("target", "targte"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/tmp/x/scene.toml:") && e.contains("targte"),
            "{e}"
        );
        let e = parse(&format!("{MINIMAL}two_sided = \"yes\"\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("scene.toml:8"), "{e}");
        let e = parse(&MINIMAL.replace("[5.0, -5.0, 3.0]", "[5.0, \"a\", 3.0]"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("scene.toml:3"), "{e}");
        let e = parse("[camera\n").unwrap_err().to_string();
        assert!(e.contains("scene.toml:1"), "{e}");
    }

    #[test]
    fn semantic_errors_are_explained() {
        let e = parse(&MINIMAL.replace("target = [0.0, 0.0, 1.0]", "target = [5.0, -5.0, 3.0]"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("coincide"), "{e}");
        let e = parse(&format!("{MINIMAL}[[model.instance]]\nscale = 0.0\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("scale"), "{e}");
        let e = parse(&MINIMAL.replace("[[model]]\nfile = \"teapot.bpt\"", ""))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no [[model]]"), "{e}");
    }

    #[test]
    fn grids_multiply_instances() {
        let text = format!(
            "{MINIMAL}[[model.instance]]\ngrid = {{ count = [3, 2, 1], step = [1.0, 2.0, 0.0] }}\n[[model.instance]]\ntranslate = [9.0, 0.0, 0.0]\n"
        );
        let s = parse(&text).unwrap();
        assert_eq!(s.models[0].instances.len(), 7);
        let last_grid = s.models[0].instances[5].transform_point3(DVec3::ZERO);
        assert_eq!(last_grid, DVec3::new(2.0, 2.0, 0.0));
    }

    #[test]
    fn huge_grids_are_refused_before_anything_is_built() {
        // 10^10 copies: refused by the parser at once (this used to run until
        // killed), with the count and the memory it would need.
        let text = format!(
            "{MINIMAL}[[model.instance]]\ngrid = {{ count = [100000, 100000, 1], step = [1.0, 1.0, 0.0] }}\n"
        );
        let t = std::time::Instant::now();
        let e = parse(&text).unwrap_err().to_string();
        assert!(t.elapsed().as_secs_f64() < 1.0);
        assert!(e.contains("10,000,000,000 instances"), "{e}");
        assert!(e.contains("1.8 TiB"), "{e}");
        assert!(e.contains("at most 16,777,215 base patches"), "{e}");
        // Few enough instances, too many patches: refused when the model's
        // size is known, before any patch is baked.
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        let text = format!(
            "{}[[model.instance]]\ngrid = {{ count = [1000, 600, 1], step = [1.0, 1.0, 0.0] }}\n",
            MINIMAL.replace("teapot.bpt", "models/teapot.bpt")
        );
        let scene = Scene::parse(&dir.join("big.toml"), &text).unwrap();
        let e = scene.geometry().unwrap_err().to_string();
        assert!(e.contains("19,200,000 base patches"), "{e}");
        assert!(e.contains("3.5 GiB"), "{e}");
    }

    #[test]
    fn a_model_error_names_the_model_once_and_not_the_scene() {
        let text = MINIMAL.replace("teapot.bpt", "no-such-model.obj");
        let scene = Scene::parse(Path::new("/tmp/x/scene.toml"), &text).unwrap();
        let e = scene.geometry().unwrap_err();
        assert!(
            matches!(&e, SceneError::Model { scene, .. } if scene == Path::new("/tmp/x/scene.toml"))
        );
        let shown = e.to_string();
        assert!(!shown.contains("scene.toml"), "{shown}");
        assert!(
            shown.starts_with("model 'model 1': /tmp/x/no-such-model.obj: "),
            "{shown}"
        );
        assert_eq!(shown.matches("No such file").count(), 1, "{shown}");
    }

    #[test]
    fn boundary_is_a_model_option() {
        let text = MINIMAL.replace(
            "file = \"teapot.bpt\"",
            "file = \"c.obj\"\nboundary = \"edge-only\"",
        );
        let s = parse(&text).unwrap();
        assert_eq!(s.models[0].options.boundary, Some(BoundaryRule::EdgeOnly));
        let e = parse(&text.replace("edge-only", "smooth"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("scene.toml:8") && e.contains("none, edge-only, edge-and-corner"),
            "{e}"
        );
    }

    #[test]
    fn fvar_is_a_model_option() {
        let text = MINIMAL.replace("file = \"teapot.bpt\"", "file = \"c.obj\"\nfvar = \"all\"");
        let s = parse(&text).unwrap();
        assert_eq!(s.models[0].options.fvar, FvarRule::All);
        let plain = parse(MINIMAL).unwrap();
        assert_eq!(plain.models[0].options.fvar, FvarRule::CornersOnly);
        let e = parse(&text.replace("\"all\"", "\"smooth\""))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("scene.toml:8") && e.contains("expected corners-only or all"),
            "{e}"
        );
    }

    #[test]
    fn path_camera_interpolates_keyframes() {
        let text = format!(
            "{MINIMAL}[camera_path]\nframes = 10\n[[camera_path.key]]\nposition = [7.0, -5.0, 3.0]\ntarget = [0.0, 0.0, 1.0]\n"
        );
        let s = parse(&text).unwrap();
        assert_eq!(s.frame_count(), 2);
        assert_eq!(s.path_camera(0.5).position, [6.0, -5.0, 3.0]);
        assert_eq!(s.frame_camera(1).unwrap().position[0], 7.0);
        assert!(s.frame_camera(2).is_none());
    }

    #[test]
    fn orbits_parse_and_bad_ones_are_explained() {
        let orbit = "[camera_orbit]\ncenter = [0.0, 0.0, 1.0]\ndistance = [2.0, 6.0]\nheight = [0.5, 3.0]\nframes = 12\n";
        let s = parse(&format!("{MINIMAL}{orbit}")).unwrap();
        let o = s.orbit.unwrap();
        assert_eq!((o.frames, o.turns, o.fov_y_deg), (12, 1.0, 45.0));
        assert!(parse(MINIMAL).unwrap().orbit.is_none());
        let e = parse(&format!(
            "{MINIMAL}{}",
            orbit.replace("[2.0, 6.0]", "[6.0, 2.0]")
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("[camera_orbit]") && e.contains("nearest"), "{e}");
        let e = parse(&format!("{MINIMAL}{orbit}radius = 3.0\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("scene.toml:") && e.contains("radius"), "{e}");
    }
}
