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
//! in [`METHODS`].

pub mod corners;
pub mod cudatess;
pub mod ground_truth;
pub mod levels;
pub mod subdiv;
pub mod subdiv_indirect;
pub mod tess;

use std::any::Any;

use serde_json::Value;

use crate::draw::{DrawPath, ReadyStage};
use crate::frame::{FrameOut, FrameRec, Retired};
use crate::gpu::{SceneGpu, SceneLayout, Shaders};
use crate::patch::view::ViewParams;
use crate::scene::geometry::SceneGeometry;
use crate::validate::MakeCheck;
use crate::vk::{Context, VkError};

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
/// the renderer rebuild its methods). Each method reads the ones it has.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodOptions {
    /// Draw path of the ready-list methods.
    pub draw: DrawPath,
    /// Initial ready-list entries (grown on overflow).
    pub ready_capacity: u32,
    /// `subdiv`: which persistent kernel (`--kernel`).
    pub kernel: subdiv::Kernel,
    /// `subdiv`: persistent workgroups (`None`: the device's default).
    pub groups: Option<u32>,
    /// `subdiv` and `subdiv-indirect`: bytes of node memory of the level
    /// schedule (rounds take chunks of a depth that fit it).
    pub node_memory: u64,
    /// `subdiv`: polls without progress before the level kernel's watchdog
    /// sends the frame to the per-depth rounds.
    pub watchdog_polls: u32,
    /// `subdiv`: polls of an unchanged join count before the occupancy
    /// window closes (`None`: the device's default).
    pub join_polls: Option<u32>,
    /// Test-only faults of the persistent level kernel (`FAULT_*`).
    pub level_faults: u32,
    /// `subdiv --kernel queue`: work-queue entries.
    pub queue_capacity: u32,
    /// `subdiv --kernel queue`: polls without progress before it gives up.
    pub idle_poll_cap: u32,
    /// `subdiv --kernel queue`: deque entries per workgroup (tests lower it).
    pub deque_capacity: u32,
    /// `subdiv --kernel queue`: base patches per claim (0: spread over the
    /// workgroups; tests fill the deque with it).
    pub base_batch: u32,
    /// `subdiv --kernel queue`: sort the ready list before drawing
    /// (deterministic images; the level kernels need no sort).
    pub sort: bool,
    /// `ground-truth`: grid cells per patch side.
    pub grid: u32,
    /// `ground-truth`: the most triangles one part of a frame (one
    /// submission, one bounded fence wait) draws; see
    /// `ground_truth::plan_parts`.
    pub part_triangles: u64,
    /// `subdiv-indirect`: the deepest level (at most l_max = 10).
    pub max_depth: u32,
    /// Test-only fault for `subdiv --kernel queue`: one phantom item in
    /// flight that never completes, so the kernel can only end through its
    /// iteration cap.
    pub plant_endless_loop: bool,
    /// Samples per pixel of the draw target (1: no multisampling). The
    /// draw pipelines are made for it.
    pub samples: u32,
    /// `cudatess`: interior vertices by forward differencing along rows
    /// instead of evaluating each one.
    pub forward_differencing: bool,
    /// `cudatess`: the vertex and index buffers' first capacities instead
    /// of the defaults (small ones make the first frames grow them).
    pub cudatess_capacity: Option<(u32, u32)>,
    /// `subdiv` (level kernels) and `subdiv-indirect`: occlusion culling in
    /// two phases against a depth pyramid (off here, so the oracle
    /// comparisons see every node; the command line turns it on).
    pub occlusion: bool,
}

impl MethodOptions {
    /// The defaults with draw path `draw`.
    pub fn new(draw: DrawPath) -> Self {
        Self {
            draw,
            ready_capacity: 1 << 18,
            kernel: subdiv::Kernel::Levels,
            groups: None,
            node_memory: levels::DEFAULT_NODE_MEMORY,
            watchdog_polls: levels::DEFAULT_WATCHDOG_POLLS,
            join_polls: None,
            level_faults: 0,
            queue_capacity: 1 << 19,
            idle_poll_cap: subdiv::DEFAULT_IDLE_POLL_CAP,
            deque_capacity: crate::constants::SUBDIV_LOCAL_CAP,
            base_batch: 0,
            sort: true,
            grid: ground_truth::DEFAULT_GRID,
            part_triangles: ground_truth::PART_TRIANGLES,
            max_depth: subdiv_indirect::DEFAULT_MAX_DEPTH,
            samples: 1,
            plant_endless_loop: false,
            forward_differencing: false,
            cudatess_capacity: None,
            occlusion: false,
        }
    }
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
    /// Whether `bench` measures it when `--methods` is not given (the
    /// methods the paper compares; not the reference it compares them
    /// with, nor the worked example).
    pub benched: bool,
    /// What the depth heat map's colours mean for it (the window's legend).
    pub heat_map: &'static str,
    /// Its own `validate` checks, beyond those every method gets (the
    /// oracle comparisons of a ready list, occlusion culling, the hole test).
    pub checks: Option<MakeCheck>,
    /// Makes the method.
    pub build: fn(&mut MethodSetup<'_>) -> Result<Box<dyn Method>, RenderError>,
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
    };

    /// What a subdivision method with a ready list reads: all but the grid.
    pub const SUBDIVIDES: Reads = Reads {
        grid: false,
        ..Reads::ALL
    };

    /// What a tessellator reads: it sets its levels from ε alone and draws
    /// itself.
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
        let reference = ground_truth::INFO.name;
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
            assert_eq!(r.grid, m.name == ground_truth::INFO.name, "{}", m.name);
        }
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
