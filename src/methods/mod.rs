//! The rendering methods behind one interface, [`Method`], and the registry
//! the command line picks them from ([`METHODS`]).
//!
//! A method records everything between the start of a frame and a drawn
//! image: its own passes and the draw into the frame's target. There are two
//! kinds, and the interface fits both:
//! - *ready-list producers* (`subdiv`, `subdiv-indirect`) fill a list
//!   of QuadNodes and hand it to the shared [`ReadyStage`] (sort, mesh or
//!   fallback draw path), which is also what validation compares with the
//!   CPU oracle;
//! - *self-drawing* methods (`ground-truth`, `tess`, `tess-reparam`,
//!   `cudatess`) record their own draw with the same fragment shading.
//!
//! A method declares what it can do in its [`MethodInfo`], and nothing
//! outside its file names it: a scene with rational patches (weights other
//! than 1) or PN triangles is only accepted by methods whose
//! [`MethodInfo::rational`] or [`MethodInfo::pn`] says so (the others refuse
//! it with a sentence rather than draw it wrong), the window greys out the
//! controls a method does not read ([`MethodInfo::reads`]), and `validate`
//! runs the method's own checks ([`MethodInfo::checks`], in the method's
//! folder, which reach its concrete type through [`Method::downcast`]).
//!
//! Adding a method means a new file here with a [`MethodInfo`] and one line
//! in [`METHODS`]. Its knobs, if it has any, are an `Options` section in
//! the same file (fields, flags, defaults, one check), and a field of
//! [`PerMethod`].

pub mod checks;
pub mod corners;
pub mod cudatess;
pub mod edges;
pub mod ground_truth;
pub mod levels;
pub mod subdiv;
pub mod subdiv_indirect;
pub mod targets;
pub mod tess;

use std::any::Any;

use serde_json::Value;

use crate::draw::{DrawPath, ReadyStage};
use crate::frame::{FrameOut, FrameRec, Retired};
use crate::gpu::blocks::BlockEntry;
use crate::gpu::{SceneGpu, SceneLayout, Shaders};
use crate::patch::view::ViewParams;
use crate::scene::geometry::SceneGeometry;
use crate::vk::{Context, VkError};
use checks::MakeCheck;
use targets::Target;

/// What can go wrong while rendering with a method.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The Vulkan layer failed.
    #[error(transparent)]
    Vk(#[from] VkError),
    /// A method's shaders reported a failure (iteration cap, overflow that
    /// could not be fixed by growing buffers).
    #[error("method `{method}`: {message}")]
    Method {
        /// The method.
        method: &'static str,
        /// What its shaders reported, as a sentence.
        message: String,
    },
    /// The request cannot be served (unknown method, bad option).
    #[error("{0}")]
    Request(String),
}

/// Knobs of the methods, fixed when a method is made (changing them makes
/// the renderer rebuild its methods or reconfigure them): the ones several
/// methods read, then each method's own section ([`PerMethod`]).
#[derive(Clone, Debug, PartialEq)]
pub struct MethodOptions {
    /// Draw path of the ready-list methods.
    pub draw: DrawPath,
    /// Initial ready-list entries (grown on overflow).
    pub ready_capacity: u32,
    /// Samples per pixel of the draw target (1: no multisampling). The
    /// draw pipelines are made for it.
    pub samples: u32,
    /// `subdiv` (level kernels) and `subdiv-indirect`: occlusion culling in
    /// two phases against a depth pyramid (off here, so the oracle
    /// comparisons see every node; the command line turns it on).
    pub occlusion: bool,
    /// Each method's own knobs.
    pub per_method: PerMethod,
}

impl MethodOptions {
    /// The defaults with draw path `draw`.
    pub fn new(draw: DrawPath) -> Self {
        Self {
            draw,
            ready_capacity: 1 << 18,
            samples: 1,
            occlusion: false,
            per_method: PerMethod::default(),
        }
    }
}

/// The methods' own knobs, one typed section per method that has any,
/// each declared in the method's file as its `Options`: the fields, their
/// flags (a clap group under the method's heading in `--help`; knobs that
/// only tests and profiling set have none), the defaults (the flags', see
/// [`cli_defaults`]) and one `check`. The command line flattens this into
/// the flags of the commands that render, `GpuRequest` carries it, and
/// [`PerMethod::check`] refuses bad values, in the flag's words, before any
/// GPU work and wherever the renderer takes new knobs.
#[derive(Clone, Debug, Default, PartialEq, Eq, clap::Args)]
pub struct PerMethod {
    /// The level schedule's, which `subdiv` and `subdiv-indirect` share.
    #[command(flatten)]
    pub levels: levels::Options,
    /// `subdiv`'s.
    #[command(flatten)]
    pub subdiv: subdiv::Options,
    /// `subdiv-indirect`'s.
    #[command(flatten)]
    pub subdiv_indirect: subdiv_indirect::Options,
    /// `ground-truth`'s.
    #[command(flatten)]
    pub ground_truth: ground_truth::Options,
    /// `cudatess`'s.
    #[command(flatten)]
    pub cudatess: cudatess::Options,
}

impl PerMethod {
    /// The reference's grid (its cells per patch side).
    pub fn reference_grid(&self) -> u32 {
        self.ground_truth.grid
    }

    /// Sets the reference's grid.
    pub fn set_reference_grid(&mut self, grid: u32) {
        self.ground_truth.grid = grid;
    }

    /// Every section's check: the first sentence that refuses a value.
    pub fn check(&self) -> Result<(), String> {
        self.ground_truth.check()?;
        self.subdiv.check()?;
        self.levels.check()?;
        self.subdiv_indirect.check()
    }
}

/// A section's defaults: what the command line gives it when none of its
/// flags is given. Its `Default` is this, so the defaults are written once,
/// in the section's attributes, and the library's cannot drift from the
/// command line's.
pub(crate) fn cli_defaults<T: clap::Args + clap::FromArgMatches>() -> T {
    let command = T::augment_args(clap::Command::new("defaults"));
    command
        .try_get_matches_from(["defaults"])
        .and_then(|m| T::from_arg_matches(&m))
        .expect("every flag of a method's section has a default")
}

/// What a method is made with.
pub struct MethodSetup<'a> {
    /// The context.
    pub ctx: &'a Context,
    /// The renderer's shader modules.
    pub shaders: &'a mut Shaders,
    /// Set 0, which every pipeline layout starts with.
    pub scene_layout: &'a SceneLayout,
    /// The knobs.
    pub options: &'a MethodOptions,
}

/// A frame's figures: the keys every method reports, plus its own section.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MethodStats {
    /// Triangles drawn (a wedge is a triangle).
    pub triangles: u64,
    /// Triangles the draw emits that cover nothing but a primitive query
    /// still counts: the fallback path's degenerate slots for missing
    /// wedges (0 elsewhere).
    pub placeholder_triangles: u64,
    /// Patches or sub-patches dropped by frustum culling.
    pub culled_patches: u64,
    /// The method's own figures, in a stable order (`method_stats` in the
    /// stats JSON).
    pub own: Vec<(&'static str, Value)>,
}

impl MethodStats {
    /// One of the method's own figures as an integer.
    pub fn get_u64(&self, key: &str) -> Option<u64> {
        self.own
            .iter()
            .find(|(k, _)| *k == key)
            .and_then(|(_, v)| v.as_u64())
    }
}

/// How a frame ended for its method.
pub enum Finished {
    /// The frame is complete.
    Done(MethodStats),
    /// The frame is incomplete, the method has fixed the cause (e.g. grown
    /// a list that overflowed) and the same view should be drawn again.
    Redo {
        /// Why, for the log.
        reason: String,
    },
}

/// Any sized type as [`Any`]: the supertrait that lets a `dyn Method` be
/// asked for its concrete type ([`Method::downcast`]) without the trait
/// naming any implementor.
pub trait AsAny: Any {
    /// `self` as [`Any`].
    fn as_any(&self) -> &dyn Any;
}

impl<T: Any> AsAny for T {
    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// A rendering method.
pub trait Method: AsAny {
    /// The registry name.
    fn name(&self) -> &'static str;

    /// How it gets triangles to the rasterizer, in words (`mesh`,
    /// `fallback`, `grid`): a ready-list method's is its stage's path, and
    /// a self-drawing method names its own.
    fn draw_path(&self) -> &'static str {
        self.ready().map_or("self-drawn", |s| s.path().name())
    }

    /// Changes the view's criterion constants this method runs with (e.g. a
    /// lower depth limit); the renderer applies it before uploading them.
    fn adjust_view(&self, _params: &mut ViewParams) {}

    /// Records the frame: the method's passes and its draw into
    /// `f.target` (begun and ended by the method), and copies out what
    /// [`Method::finish`] reads.
    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError>;

    /// Reads the frame's figures once its fence has signalled; buffers it
    /// replaces go to `out.retired`.
    fn finish(&mut self, out: &mut FrameOut<'_>) -> Result<Finished, RenderError>;

    /// Applies changed knobs in place where that is cheap (a new grid, a
    /// flag), putting replaced resources in `retired`; returns false when
    /// the method must be made again instead.
    fn reconfigure(
        &mut self,
        _setup: &mut MethodSetup<'_>,
        _retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        Ok(false)
    }

    /// GPU memory the method holds, by purpose, in bytes.
    fn memory(&self) -> Vec<(&'static str, u64)>;

    /// The ready list and its draw stage, for methods that produce one (the
    /// oracle comparisons of `validate` apply to exactly these).
    fn ready(&self) -> Option<&ReadyStage> {
        None
    }

    /// Whether the frame is drawn with mesh pipelines (the triangle count
    /// then comes from the mesh-primitives query).
    fn uses_mesh_shaders(&self) -> bool {
        self.ready().is_some_and(|s| s.path() == DrawPath::Mesh)
    }

    /// Whether the method draws the crack-closing wedges (the hole test
    /// then also looks with them off, to show it can see cracks). The ready
    /// stage's draw is what draws them, so exactly the ready-list methods do.
    fn has_wedges(&self) -> bool {
        self.ready().is_some()
    }

    /// Whether occlusion culling ([`MethodOptions::occlusion`]) takes effect
    /// in the method as made, whether or not it is on now: `validate` then
    /// checks that turning it on changes no pixel.
    fn culls_occluded(&self) -> bool {
        false
    }
}

impl dyn Method {
    /// The method as its concrete type `T`, if it is one (a method's own
    /// checks read its buffers through this).
    pub fn downcast<T: Method>(&self) -> Option<&T> {
        self.as_any().downcast_ref()
    }
}

/// A registry entry.
pub struct MethodInfo {
    /// Command-line name.
    pub name: &'static str,
    /// One line for `--help`.
    pub about: &'static str,
    /// Whether it draws rational patches (scenes with weights other than 1).
    pub rational: bool,
    /// Whether it draws PN-triangle models (`surface = "pn-triangles"`).
    pub pn: bool,
    /// The view settings it reads.
    pub reads: Reads,
    /// The part it plays in the comparisons.
    pub role: Role,
    /// The targets `bench`'s report judges it by (none: only measured).
    pub targets: &'static [Target],
    /// What the depth heat map's colours mean for it (the window's legend).
    pub heat_map: &'static str,
    /// What the wedge colour marks in its drawing (the window's legend):
    /// the triangles that close cracks, or that nothing does.
    pub seams: &'static str,
    /// Its own `validate` checks, beyond those every method gets (the
    /// oracle comparisons of a ready list, occlusion culling, the hole test).
    pub checks: Option<MakeCheck>,
    /// Its own constant blocks (`gpu::blocks::block::<ItsPush>`), which
    /// `tests/blocks.rs` holds against the shaders' (the shared ones are
    /// `gpu::blocks::shared_blocks`).
    pub blocks: &'static [fn() -> BlockEntry],
    /// Makes the method.
    pub build: fn(&mut MethodSetup<'_>) -> Result<Box<dyn Method>, RenderError>,
}

/// The part a method plays in the comparisons `bench`, `render --flip`
/// and `validate` make. Exactly one entry is the reference and one the
/// baseline ([`reference`], [`baseline`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A method the paper compares: `bench` measures it unless `--methods`
    /// says otherwise.
    Compared,
    /// The method every compared one is measured against at equal error
    /// (`bench`'s equal-error tables); compared itself too.
    Baseline,
    /// The image every method's error is measured against (FLIP, the
    /// geometric error, the hole test's look at what each method covers).
    Reference,
    /// A worked example of adding a method; not compared.
    Example,
}

impl MethodInfo {
    /// Whether `bench` measures it when `--methods` is not given.
    pub fn benched(&self) -> bool {
        matches!(self.role, Role::Compared | Role::Baseline)
    }
}

/// Every host constant block, each once: the shared ones and those the
/// registry's entries declare (two methods may share one, as the level
/// methods share `LevelPush`).
pub fn all_blocks() -> Vec<BlockEntry> {
    let mut all = crate::gpu::blocks::shared_blocks();
    // The levels of detail's cull, which every method's frame may end with
    // (registered here: src/lod uses gpu::blocks, so gpu::blocks cannot
    // name it).
    all.push(crate::gpu::blocks::block::<crate::lod::gpu::LodCullPush>());
    for make in METHODS.iter().flat_map(|m| m.blocks) {
        let b = make();
        if !all.iter().any(|a| a.0 == b.0) {
            all.push(b);
        }
    }
    all
}

/// The method the command line draws with unless told otherwise.
pub const DEFAULT_METHOD: &str = subdiv::INFO.name;

/// The reference's grid unless told otherwise (`--grid`).
pub const REFERENCE_DEFAULT_GRID: u32 = ground_truth::DEFAULT_GRID;
/// The reference's largest grid.
pub const REFERENCE_MAX_GRID: u32 = ground_truth::MAX_GRID;

/// The entry with role `role` (the registry has exactly one reference and
/// one baseline: a test says so).
fn the(role: Role) -> &'static MethodInfo {
    METHODS
        .iter()
        .find(|m| m.role == role)
        .expect("the registry has a method in every singular role")
}

/// The reference image's method.
pub fn reference() -> &'static MethodInfo {
    the(Role::Reference)
}

/// The baseline of the comparisons at equal error.
pub fn baseline() -> &'static MethodInfo {
    the(Role::Baseline)
}

/// The names of the methods whose [`Reads`] satisfy `pred`, as a sentence
/// ("`a` and `b`").
pub fn names_that_read(pred: impl Fn(&Reads) -> bool) -> String {
    let names: Vec<String> = METHODS
        .iter()
        .filter(|m| pred(&m.reads))
        .map(|m| format!("`{}`", m.name))
        .collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

/// Every method that is built, by command-line name.
pub const METHODS: &[MethodInfo] = &[
    subdiv::INFO,
    subdiv_indirect::INFO,
    ground_truth::INFO,
    tess::INFO,
    tess::INFO_REPARAM,
    cudatess::INFO,
    corners::INFO,
];

/// The view settings a method reads, beyond ε and culling by the frustum,
/// which every method but the ground truth reads: the window greys out the
/// controls of the others (they would change nothing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reads {
    /// The draw path (mesh or fallback) of the ready-list methods.
    pub draw_path: bool,
    /// The pixel tolerance ε.
    pub eps: bool,
    /// The distance blend λ of the subdivision criterion.
    pub lambda: bool,
    /// The deepest subdivision level.
    pub l_max: bool,
    /// The split mode (`iso` or `aniso`).
    pub split: bool,
    /// Crack-closing wedges on or off.
    pub wedges: bool,
    /// Back-face culling on or off.
    pub backface: bool,
    /// Occlusion culling on or off (the level kernels' two phases).
    pub occlusion: bool,
    /// The ground truth's grid.
    pub grid: bool,
    /// A model's displacement (scene key `displacement`): a method that
    /// does not read it draws displaced models undisplaced.
    pub displacement: bool,
}

impl Reads {
    /// Every setting: what a name no method has reads, so that nothing is
    /// greyed out on a guess.
    pub const ALL: Reads = Reads {
        draw_path: true,
        eps: true,
        lambda: true,
        l_max: true,
        split: true,
        wedges: true,
        backface: true,
        occlusion: true,
        grid: true,
        displacement: true,
    };

    /// What a subdivision method with a ready list reads: all but the grid.
    pub const SUBDIVIDES: Reads = Reads {
        grid: false,
        ..Reads::ALL
    };

    /// What a tessellator reads: it sets its levels from ε (and a
    /// displaced model's bound) alone and draws itself.
    pub const TESSELLATES: Reads = Reads {
        draw_path: false,
        lambda: false,
        l_max: false,
        split: false,
        wedges: false,
        occlusion: false,
        ..Reads::SUBDIVIDES
    };
}

/// What method `name` reads ([`MethodInfo::reads`]); an unknown name reads
/// everything.
pub fn reads(name: &str) -> Reads {
    METHODS
        .iter()
        .find(|m| m.name == name)
        .map_or(Reads::ALL, |m| m.reads)
}

/// Names reserved for methods still to come (none at present; a name put
/// here is refused with "not built yet" instead of "unknown").
pub const PLANNED: &[&str] = &[];

/// The registry entry named `name`; unknown and unbuilt names get their
/// own sentences.
pub fn find(name: &str) -> Result<&'static MethodInfo, RenderError> {
    find_in(name, METHODS, PLANNED)
}

/// Refuses to draw `scene` with method `info` when the scene has rational
/// patches the method cannot draw.
pub fn check_rational(info: &MethodInfo, scene: &SceneGpu) -> Result<(), RenderError> {
    refuse(
        info,
        scene.rational_patches as usize,
        scene.count as usize,
        0,
    )
}

/// Refuses to draw `scene` with method `info` when the scene has
/// PN-triangle models (`surface = "pn-triangles"`), which only `cudatess`
/// tessellates (and `ground-truth` draws as uniform grids, the reference).
pub fn check_pn(info: &MethodInfo, scene: &SceneGpu) -> Result<(), RenderError> {
    refuse(info, 0, scene.count as usize, scene.pn.count() as usize)
}

/// [`check_rational`] and [`check_pn`] on the host's geometry, before any
/// GPU work (`bench` plans its methods with it).
pub fn check_geometry(info: &MethodInfo, geo: &SceneGeometry) -> Result<(), RenderError> {
    refuse(
        info,
        geo.rational_patches(),
        geo.patches.len(),
        geo.pn.triangles.len(),
    )
}

/// The sentence that refuses method `info` a scene with `rational` of its
/// `patches` base patches rational and `pn` PN triangles, if it must.
fn refuse(
    info: &MethodInfo,
    rational: usize,
    patches: usize,
    pn: usize,
) -> Result<(), RenderError> {
    if rational > 0 && !info.rational {
        let able: Vec<&str> = METHODS
            .iter()
            .filter(|m| m.rational)
            .map(|m| m.name)
            .collect();
        return Err(RenderError::Request(format!(
            "method `{}` cannot draw rational patches, and {rational} of the scene's {patches} \
             base patches have weights other than 1; use {}",
            info.name,
            able.join(" or ")
        )));
    }
    if pn > 0 && !info.pn {
        // The ground truth is named apart: it is the reference, not a method
        // to draw the scene with.
        let reference = reference().name;
        let able: Vec<&str> = METHODS
            .iter()
            .filter(|m| m.pn && m.name != reference)
            .map(|m| m.name)
            .collect();
        return Err(RenderError::Request(format!(
            "method `{}` cannot draw PN triangles, and the scene has {pn} of them \
             (models with surface = \"pn-triangles\"); use {} (or {reference}, the reference)",
            info.name,
            able.join(" or ")
        )));
    }
    Ok(())
}

/// [`find`] over the registry `methods` and the reserved names `planned`.
fn find_in<'a>(
    name: &str,
    methods: &'a [MethodInfo],
    planned: &[&str],
) -> Result<&'a MethodInfo, RenderError> {
    if let Some(m) = methods.iter().find(|m| m.name == name) {
        return Ok(m);
    }
    let built: Vec<&str> = methods.iter().map(|m| m.name).collect();
    Err(RenderError::Request(if planned.contains(&name) {
        format!(
            "method `{name}` is not built yet; available: {}",
            built.join(", ")
        )
    } else {
        format!("unknown method `{name}`; methods: {}", built.join(", "))
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each host block is a gapless run of fields filling a 16-byte multiple.
    #[test]
    fn fields_cover_each_block_without_gaps() {
        for (name, size, fields) in all_blocks() {
            let mut end = 0;
            for f in &fields {
                assert_eq!(f.offset, end, "{name}.{} starts after a gap", f.name);
                end = f.offset + f.size;
            }
            assert_eq!(end, size, "{name}: fields do not fill the struct");
            assert_eq!(size % 16, 0, "{name}: not a 16-byte multiple");
        }
    }

    /// Every built method says what it reads (none reads everything, as an
    /// unknown name does), only the subdivision methods read λ, l_max and
    /// wedges.
    #[test]
    fn every_method_says_what_it_reads() {
        let unknown = reads("no such method");
        assert_eq!(unknown, Reads::ALL);
        for m in METHODS {
            let r = reads(m.name);
            assert_eq!(r, m.reads, "{}", m.name);
            assert_ne!(r, unknown, "{} reads everything", m.name);
            let subdivides = m.name.starts_with("subdiv");
            assert_eq!(r.lambda && r.l_max && r.wedges, subdivides, "{}", m.name);
            assert_eq!(r.grid, m.role == Role::Reference, "{}", m.name);
        }
    }

    /// Each section's defaults (the flags') are the knobs' long-standing
    /// values, and the flags parse into the sections.
    #[test]
    fn sections_default_to_their_flags() {
        let d = PerMethod::default();
        assert_eq!(d.levels.node_memory, levels::DEFAULT_NODE_MEMORY);
        let s = &d.subdiv;
        assert_eq!((s.kernel, s.groups), (subdiv::Kernel::Levels, None));
        assert_eq!(s.watchdog_polls, levels::DEFAULT_WATCHDOG_POLLS);
        assert_eq!((s.join_polls, s.level_faults), (None, 0));
        assert_eq!(s.queue_capacity, 1 << 19);
        assert_eq!(s.idle_poll_cap, subdiv::DEFAULT_IDLE_POLL_CAP);
        assert_eq!(s.deque_capacity, crate::constants::SUBDIV_LOCAL_CAP);
        assert_eq!(s.base_batch, 0);
        assert!(s.sort && !s.plant_endless_loop);
        assert_eq!(
            d.subdiv_indirect.max_depth,
            subdiv_indirect::DEFAULT_MAX_DEPTH
        );
        assert_eq!(d.ground_truth.grid, ground_truth::DEFAULT_GRID);
        assert_eq!(d.ground_truth.part_triangles, ground_truth::PART_TRIANGLES);
        assert_eq!(d.cudatess, cudatess::Options::default());
        assert!(!d.cudatess.forward_differencing && d.cudatess.capacity.is_none());
        assert_eq!(d.check(), Ok(()));

        let parse = |args: &[&str]| {
            use clap::{Args, FromArgMatches};
            let cmd = PerMethod::augment_args(clap::Command::new("t"));
            let m = cmd.try_get_matches_from([&["t"], args].concat()).unwrap();
            PerMethod::from_arg_matches(&m).unwrap()
        };
        assert_eq!(parse(&[]), d);
        let p = parse(&[
            "--grid=16",
            "--max-depth=6",
            "--kernel=queue",
            "--groups=8",
            "--node-memory=0.5",
            "--forward-diff",
        ]);
        assert_eq!(p.ground_truth.grid, 16);
        assert_eq!(p.subdiv_indirect.max_depth, 6);
        assert_eq!(
            (p.subdiv.kernel, p.subdiv.groups),
            (subdiv::Kernel::Queue, Some(8))
        );
        assert_eq!(p.levels.node_memory, 1 << 19);
        assert!(p.cudatess.forward_differencing);
    }

    /// One check per section refuses what it must, in the flag's words.
    #[test]
    fn sections_refuse_in_their_flags_words() {
        let refused = |f: fn(&mut PerMethod)| {
            let mut o = PerMethod::default();
            f(&mut o);
            o.check().unwrap_err()
        };
        let e = refused(|o| o.ground_truth.grid = 48);
        assert!(
            e.starts_with("--grid: ") && e.contains("power of two"),
            "{e}"
        );
        let e = refused(|o| o.subdiv_indirect.max_depth = 11);
        assert_eq!(e, "--max-depth 11 is beyond l_max = 10");
        assert_eq!(
            refused(|o| o.subdiv.groups = Some(0)),
            "--groups must be at least 1"
        );
        assert_eq!(
            refused(|o| o.levels.node_memory = 0),
            "--node-memory must be positive"
        );
        let e = refused(|o| o.subdiv.deque_capacity = 0);
        assert!(e.starts_with("a deque of 0 entries"), "{e}");
    }

    /// The PN refusal names the methods that declare PN triangles, in the
    /// sentence it has always had.
    #[test]
    fn pn_refusal_names_the_able_methods() {
        let e = refuse(&subdiv::INFO, 0, 4, 2).err().unwrap().to_string();
        assert!(
            e.ends_with("use cudatess (or ground-truth, the reference)"),
            "{e}"
        );
        for m in METHODS {
            assert_eq!(refuse(m, 0, 4, 2).is_ok(), m.pn, "{}", m.name);
        }
    }

    /// One reference and one baseline, and every target holds a method
    /// against one the registry has.
    #[test]
    fn roles_are_singular_and_targets_name_registered_methods() {
        for role in [Role::Reference, Role::Baseline] {
            assert_eq!(METHODS.iter().filter(|m| m.role == role).count(), 1);
        }
        assert!(!reference().benched() && baseline().benched());
        for m in METHODS {
            for t in m.targets {
                if let targets::Target::Ratio {
                    against: targets::Against::Method(o),
                    ..
                } = t
                {
                    assert!(find(o).is_ok(), "{}: {o}", m.name);
                }
            }
        }
        assert!(find(DEFAULT_METHOD).is_ok());
        assert_eq!(
            names_that_read(|r| r.split),
            "`subdiv` and `subdiv-indirect`"
        );
    }

    #[test]
    fn names_are_unique_and_found() {
        for m in METHODS {
            assert_eq!(find(m.name).unwrap().name, m.name);
            assert!(
                !PLANNED.contains(&m.name),
                "{} is built and planned",
                m.name
            );
            assert_eq!(METHODS.iter().filter(|x| x.name == m.name).count(), 1);
        }
        // The planned-name sentence, with a stand-in reserved name.
        let e = find_in("pn-tess", METHODS, &["pn-tess"])
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("not built yet") && e.contains("subdiv"), "{e}");
        assert!(find_in("subdiv", METHODS, &["pn-tess"]).is_ok());
        let e = find("nope").err().unwrap().to_string();
        assert!(
            e.contains("unknown method") && e.contains("ground-truth"),
            "{e}"
        );
    }
}
