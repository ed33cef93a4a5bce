//! Shared setup for the integration tests: the GPU context, scenes,
//! renderers and `validate` runs here; fixtures and helpers in submodules
//! named for what they hold.
//!
//! Every GPU test in a test binary shares one validation-enabled [`Context`]
//! behind a mutex, so tests run on the device one at a time even under the
//! default parallel test runner: lavapipe's worker threads and persistent
//! kernels starve each other when two tests dispatch at once.
//!
//! The context lives in a `static` and is never dropped (Rust runs no
//! destructors for statics at exit). That leaks the instance and device at
//! process exit, which is harmless: no vkDestroyDevice call happens, so the
//! validation layer has nothing to report, and the OS reclaims the memory.
//! Tests that need to watch device destruction (leak checks) create their
//! own short-lived context instead.

#![allow(dead_code)]

pub mod cages;
pub mod cameras;
pub mod cli;
pub mod culling;
pub mod edges;
pub mod fuzz;
pub mod spirv;

use bezier_subdiv::vk::{Context, ContextOptions};
use std::ops::Deref;
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};

static GPU: OnceLock<Result<Mutex<Arc<Context>>, String>> = OnceLock::new();

/// Options every test context uses: validation on, automatic device choice.
pub fn test_options() -> ContextOptions {
    ContextOptions {
        validation: true,
        ..ContextOptions::default()
    }
}

/// Routes `log` output (validation messages included) into the test output.
pub fn init_logging() {
    let _ = env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .is_test(true)
        .try_init();
}

/// Exclusive use of the shared context for one test.
///
/// Dropping it (or calling [`Gpu::finish`]) fails the test if the validation
/// layer reported an error while it was held.
pub struct Gpu {
    guard: MutexGuard<'static, Arc<Context>>,
    checked: bool,
}

/// Locks the shared test context, creating it on first use.
pub fn gpu() -> Gpu {
    init_logging();
    let shared = GPU.get_or_init(|| {
        Context::new(&test_options())
            .map(|c| Mutex::new(Arc::new(c)))
            .map_err(|e| e.to_string())
    });
    let mutex = match shared {
        Ok(m) => m,
        Err(e) => panic!("cannot create the shared Vulkan test context: {e}"),
    };
    // A test that panicked while holding the lock leaves the context usable.
    let guard = mutex.lock().unwrap_or_else(|e| e.into_inner());
    // Errors left by an earlier (failed) test must not fail this one.
    let _ = guard.check_validation();
    Gpu {
        guard,
        checked: false,
    }
}

impl Gpu {
    /// Asserts that no validation error was reported during this test.
    pub fn finish(mut self) {
        self.checked = true;
        if let Err(e) = self.guard.check_validation() {
            panic!("{e}");
        }
    }
}

impl Gpu {
    /// The shared context as an `Arc`, for renderers.
    pub fn arc(&self) -> Arc<Context> {
        Arc::clone(&self.guard)
    }
}

impl Deref for Gpu {
    type Target = Context;

    fn deref(&self) -> &Context {
        &self.guard
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // Panicking during an unwind would abort the whole test binary.
        if self.checked || std::thread::panicking() {
            return;
        }
        if let Err(e) = self.guard.check_validation() {
            panic!("{e}");
        }
    }
}

/// A directory for what a test writes (images of failures, reports):
/// under Cargo's scratch directory for integration tests, never in the
/// source tree, so the suite runs from a read-only checkout.
pub fn output_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(tag);
    std::fs::create_dir_all(&dir).expect("create the test output directory");
    dir
}

/// A scene of `scenes/` and its geometry.
pub fn scene(
    name: &str,
) -> (
    bezier_subdiv::scene::desc::Scene,
    bezier_subdiv::scene::geometry::SceneGeometry,
) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let s = bezier_subdiv::scene::desc::Scene::load(&path).unwrap();
    let g = s.geometry().unwrap();
    (s, g)
}

/// A scene of `scenes/`, its geometry and its shading patches.
pub fn scene_with_shading(
    name: &str,
) -> (
    bezier_subdiv::scene::desc::Scene,
    bezier_subdiv::scene::geometry::SceneGeometry,
    bezier_subdiv::scene::geometry::SceneShading,
) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let s = bezier_subdiv::scene::desc::Scene::load(&path).unwrap();
    let (g, sh) = s.geometry_and_shading().unwrap();
    (s, g, sh)
}

/// A renderer on the shared context for `geo` with `method`, `size` and
/// the knobs `options` (a dark background, two frames in flight), shading
/// with the patches' own derivatives (`set_geometry` replaces them).
pub fn renderer(
    gpu: &Gpu,
    geo: &bezier_subdiv::scene::geometry::SceneGeometry,
    method: &str,
    size: (u32, u32),
    options: bezier_subdiv::methods::MethodOptions,
) -> bezier_subdiv::renderer::Renderer {
    bezier_subdiv::renderer::Renderer::new(
        gpu.arc(),
        geo,
        &bezier_subdiv::scene::geometry::SceneShading::own_derivatives(geo),
        method,
        bezier_subdiv::renderer::RendererOptions {
            size,
            background: [0.1, 0.1, 0.1, 1.0],
            frames_in_flight: 2,
            methods: options,
        },
    )
    .unwrap_or_else(|e| panic!("renderer for {method}: {e}"))
}

/// How many hole checks `validate` runs on a scene: one per distinct model
/// file that has patches (instances of one file are checked once).
#[allow(dead_code)]
pub fn distinct_models(name: &str) -> usize {
    let (_, geo) = scene(name);
    geo.models
        .iter()
        .filter(|m| m.patches_per_instance > 0)
        .map(|m| m.file.clone())
        .collect::<std::collections::HashSet<_>>()
        .len()
}

/// A path relative to the repository root.
pub fn repo_path(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// A model file of `scenes/models/`.
pub fn model_path(name: &str) -> std::path::PathBuf {
    repo_path("scenes/models").join(name)
}

/// `validate` of the scene `name` of `scenes/` with `method` at `size`,
/// validation layer on, every keyframe; the hole check (its debug images
/// under the test output) only where `holes`. A run that cannot start
/// fails the test, naming the scene and method.
pub fn validate(
    name: &str,
    method: &str,
    size: (u32, u32),
    holes: bool,
) -> bezier_subdiv::commands::validate::ValidateReport {
    use bezier_subdiv::commands::validate::{run, ValidateArgs};
    let mut gpu = bezier_subdiv::commands::GpuRequest::new(repo_path("scenes").join(name));
    gpu.size = size;
    gpu.method = method.into();
    gpu.validation = true;
    run(&ValidateArgs {
        gpu,
        frames: Vec::new(),
        skip_holes: !holes,
        debug_dir: holes.then(|| output_dir("holes")),
    })
    .unwrap_or_else(|e| panic!("validate {name} with {method}: {e:#}"))
}

/// Renders `v` and checks the frame bit for bit: the GPU's ready set
/// against `oracle` run on the method's own view (its depth limit, where it
/// has one), the captured positions and, on the fallback path, the vertex
/// words against `surfaces`; `what` names the case in a failure. Returns
/// the GPU's ready list (in GPU order) and the oracle's result.
pub fn check_frame<S: bezier_subdiv::patch::oracle::Surfaces + ?Sized>(
    r: &mut bezier_subdiv::renderer::Renderer,
    v: &bezier_subdiv::frame::View,
    what: &str,
    surfaces: &S,
    oracle: impl FnOnce(
        &bezier_subdiv::patch::view::ViewParams,
    ) -> bezier_subdiv::patch::oracle::SubdivResult,
) -> (
    Vec<bezier_subdiv::patch::quadnode::QuadNode>,
    bezier_subdiv::patch::oracle::SubdivResult,
) {
    use bezier_subdiv::constants::FLAG_WEDGES;
    use bezier_subdiv::draw::DrawPath;
    use bezier_subdiv::validate::{compare_capture, compare_ready, compare_vertices};
    let report = r.render(v).unwrap_or_else(|e| panic!("{what}: {e}"));
    let ctx = r.context().clone();
    let stage = r.method().ready().unwrap();
    let list = stage.list();
    let count = report.stats.get_u64("ready_quads").unwrap() as u32;
    let ready = list.read_ready(&ctx, count).unwrap();
    let params = r.effective_params(v);
    let oracle = oracle(&params);
    let (ok, detail) = compare_ready(&ready, &oracle.ready);
    assert!(ok, "{what}: {detail}");
    let wedges = params.flags & FLAG_WEDGES != 0;
    let capture: Vec<[f32; 4]> = list.capture.read(&ctx).unwrap();
    let (n, bad) = compare_capture(surfaces, &ready, &capture, wedges);
    assert_eq!(bad, 0, "{what}: {bad} of {n} captured positions differ");
    if stage.path() == DrawPath::Fallback {
        let words: Vec<u32> = list.vertices.read(&ctx).unwrap();
        let (n, bad) = compare_vertices(surfaces, &ready, &words, wedges);
        assert_eq!(bad, 0, "{what}: {bad} of {n} fallback vertices differ");
    }
    (ready, oracle)
}
