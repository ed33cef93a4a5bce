//! The subdivision kernels against the CPU (lavapipe with 8 worker threads,
//! validation and synchronisation validation on): the level kernels'
//! ready lists equal the CPU twin of their schedule entry for entry (and
//! the oracle's set and counts) with 8 and more workgroups, at any depth in
//! bounded node memory; the persistent kernel's watchdog sends a frame to
//! the per-depth rounds; the queue kernel against the oracle, its tiny
//! queue, its deque one slot from full and its iteration cap; the limits
//! refused with a sentence.

mod common;

use bezier_subdiv::constants::*;
use bezier_subdiv::draw::{indirect_args, DrawPath};
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::levels::{canonical_ready, levels_for, GpuSubdivStats, LevelPlan};
use bezier_subdiv::methods::subdiv::Kernel;
use bezier_subdiv::methods::{MethodOptions, RenderError};
use bezier_subdiv::patch::oracle::{subdivide_parallel_weighted, triangle_counts};
use bezier_subdiv::patch::quadnode::QuadNode;
use bezier_subdiv::renderer::{FrameReport, Renderer};
use bezier_subdiv::scene::camera::Camera;
use bezier_subdiv::scene::geometry::SceneGeometry;

/// Every test of this binary shares one context made with 8 lavapipe
/// worker threads (read when the device is made), more than this
/// machine's cores, so workgroups really interleave.
fn gpu() -> common::Gpu {
    static THREADS: std::sync::Once = std::sync::Once::new();
    THREADS.call_once(|| std::env::set_var("LP_NUM_THREADS", "8"));
    common::gpu()
}

struct Run {
    /// The ready list in the GPU's order.
    ready: Vec<QuadNode>,
    stats: GpuSubdivStats,
    /// The whole counters buffer, the fallback's chunk arguments included.
    counters: Vec<u32>,
    report: FrameReport,
}

impl Run {
    fn own(&self, key: &str) -> u64 {
        self.report
            .stats
            .get_u64(key)
            .unwrap_or_else(|| panic!("no `{key}` in {:?}", self.report.stats.own))
    }

    fn kernel(&self) -> String {
        let own = &self.report.stats.own;
        let k = own.iter().find(|(k, _)| *k == "kernel");
        k.map_or(String::new(), |(_, v)| v.as_str().unwrap_or("").to_string())
    }
}

fn view(cam: &Camera, size: (u32, u32), eps: f64, lambda: f64) -> View {
    View::new(cam, size, eps, lambda, SHADE_NORMAL)
}

fn options(f: impl FnOnce(&mut MethodOptions)) -> MethodOptions {
    let mut o = MethodOptions::new(DrawPath::Mesh);
    f(&mut o);
    o
}

/// Renders `v` and reads the ready list (in GPU order) and the counters.
fn run_gpu(r: &mut Renderer, v: &View) -> Result<Run, RenderError> {
    let report = r.render(v)?;
    let ctx = r.context().clone();
    let list = r.method().ready().expect("a ready-list method").list();
    let counters = list.read_counters(&ctx)?;
    let stats = GpuSubdivStats::from_counters(&counters);
    let ready = list.read_ready(&ctx, stats.ready_quads)?;
    Ok(Run {
        ready,
        stats,
        counters,
        report,
    })
}

/// The oracle's set and counts, whatever the order.
fn check_against_oracle(r: &Renderer, geo: &SceneGeometry, v: &View, run: &Run) {
    assert_eq!(run.stats.errors, 0, "{:?}", run.stats.error_message());
    let vp = r.effective_params(v);
    let oracle = subdivide_parallel_weighted(&geo.patches, &geo.weights, &geo.flags, &vp, 2);
    let (mut got, mut want) = (run.ready.clone(), oracle.ready.clone());
    got.sort();
    want.sort();
    assert_eq!(got.len(), want.len(), "ready count GPU vs oracle");
    assert!(got == want, "ready sets differ");
    let s = oracle.stats;
    let g = run.stats;
    // The level kernels cull whole instances by their boxes before depth
    // 0; the oracle processes (and culls) those patches one by one.
    let whole = run.report.stats.get_u64("instance_culled_patches");
    assert_eq!(
        (
            u64::from(g.nodes_processed) + whole.unwrap_or(0),
            u64::from(g.culled_patches),
            u64::from(g.backface_culled)
        ),
        (s.nodes_processed, s.culled_patches, s.backface_culled)
    );
    assert_eq!(
        (g.max_depth, u64::from(g.nodes_at_lmax)),
        (s.max_depth, s.nodes_at_lmax)
    );
    let (tris, wedges) = triangle_counts(&oracle.ready, vp.flags & FLAG_WEDGES != 0);
    assert_eq!(
        (u64::from(g.triangles), u64::from(g.wedge_triangles)),
        (tris, wedges)
    );
    // The shaders' `write_ready_args` and the host's twin agree on every
    // indirect argument, the fallback's chunks included.
    for (word, value) in indirect_args(g.ready_quads) {
        assert_eq!(run.counters[word as usize], value, "counters[{word}]");
    }
}

/// A level kernel's frame: the oracle's set, and the CPU twin's list in
/// the same order, in as many rounds.
fn check_canonical(r: &mut Renderer, geo: &SceneGeometry, v: &View, what: &str) -> Run {
    let run = run_gpu(r, v).unwrap_or_else(|e| panic!("{what}: {e}"));
    check_against_oracle(r, geo, v, &run);
    let vp = r.effective_params(v);
    let plan = LevelPlan {
        chunk: run.own("chunk_nodes") as u32,
        levels: levels_for(vp.flags & FLAG_ANISO != 0),
    };
    let twin = canonical_ready(
        &geo.patches,
        &geo.weights,
        &geo.flags,
        &r.scene().instance_records,
        &vp,
        plan,
    );
    assert!(
        run.ready == twin.ready,
        "{what}: the ready list is not in the canonical order"
    );
    assert_eq!(run.own("rounds"), u64::from(twin.rounds), "{what}: rounds");
    assert_eq!(
        run.own("rounds_split"),
        u64::from(twin.split_rounds),
        "{what}: rounds in parts"
    );
    run
}

#[test]
fn level_kernels_write_the_canonical_list_with_8_and_more_workgroups() {
    let gpu = gpu();
    for (name, size) in [("teapot.toml", (640, 360)), ("kitchen.toml", (320, 180))] {
        let (s, geo) = common::scene(name);
        let mut indirect = common::renderer(&gpu, &geo, "subdiv-indirect", size, options(|_| {}));
        let mut persistent: Vec<(u32, Renderer)> = [8, 16]
            .into_iter()
            .map(|g| {
                let o = options(|o| o.per_method.subdiv.groups = Some(g));
                (g, common::renderer(&gpu, &geo, "subdiv", size, o))
            })
            .collect();
        for frame in 0..s.frame_count().min(3) {
            let cam = s.frame_camera(frame).unwrap();
            for (eps, lambda) in [(1.0, 0.5), (0.5, 0.0), (2.0, 1.0)] {
                let v = view(&cam, size, eps, lambda);
                let what = format!("{name} frame {frame} eps {eps} lambda {lambda}");
                let a = check_canonical(&mut indirect, &geo, &v, &format!("{what} per-depth"));
                for (g, r) in persistent.iter_mut() {
                    if *g > 8 && frame > 0 {
                        continue;
                    }
                    let b = check_canonical(r, &geo, &v, &format!("{what} {g} groups"));
                    assert_eq!(b.kernel(), "levels", "{what}");
                    let joined = b.own("workgroups_joined");
                    assert!((1..=8).contains(&joined), "{what}: {joined} joined");
                    println!(
                        "{what}: {} ready, depth {}, {} rounds; {g} launched, {joined} joined, \
                         {} barrier polls, atomics/node {:.4} (per-depth {:.4})",
                        b.stats.ready_quads,
                        b.stats.max_depth,
                        b.own("rounds"),
                        b.own("barrier_polls"),
                        f64::from(b.stats.global_atomics) / f64::from(b.stats.nodes_processed),
                        f64::from(a.stats.global_atomics) / f64::from(a.stats.nodes_processed),
                    );
                }
            }
        }
    }
    gpu.finish();
}

/// Under 1:2 splits (`--split aniso`, FLAG_ANISO in the view) every kernel
/// still writes the oracle's set, and the level kernels the CPU twin's
/// list in its order: the teapot, the kitchen and the four-patch tube,
/// whose nodes split 1:2 along the straight direction.
#[test]
fn aniso_splits_equal_the_oracle_on_every_kernel() {
    let gpu = gpu();
    let cases = [
        ("teapot.toml", (640, 360)),
        ("kitchen.toml", (320, 180)),
        ("cylinder.toml", (640, 360)),
    ];
    for (name, size) in cases {
        let (s, geo) = common::scene(name);
        let mut indirect = common::renderer(&gpu, &geo, "subdiv-indirect", size, options(|_| {}));
        let o = options(|o| o.per_method.subdiv.groups = Some(8));
        let mut persistent = common::renderer(&gpu, &geo, "subdiv", size, o);
        let mut queued = common::renderer(
            &gpu,
            &geo,
            "subdiv",
            size,
            queue(|o| o.per_method.subdiv.groups = Some(8)),
        );
        for frame in 0..s.frame_count().min(2) {
            let cam = s.frame_camera(frame).unwrap();
            for (eps, lambda) in [(1.0, 0.5), (0.5, 0.0)] {
                let mut v = view(&cam, size, eps, lambda);
                v.params.flags |= FLAG_ANISO;
                let what = format!("{name} frame {frame} eps {eps} lambda {lambda} aniso");
                let a = check_canonical(&mut indirect, &geo, &v, &format!("{what} per-depth"));
                let b = check_canonical(&mut persistent, &geo, &v, &format!("{what} persistent"));
                assert_eq!(a.ready, b.ready, "{what}: the two level methods differ");
                let c = run_gpu(&mut queued, &v).unwrap();
                check_against_oracle(&queued, &geo, &v, &c);
                let halved = a.ready.iter().filter(|q| q.du() != q.dv()).count();
                println!(
                    "{what}: {} ready, {halved} with unequal depths, depth {}",
                    a.stats.ready_quads, a.stats.max_depth
                );
                assert!(halved > 0, "{what}: no 1:2 node, the case proves nothing");
            }
        }
    }
    gpu.finish();
}

/// The case that showed the level kernels writing past their node memory
/// (issue 36): one patch whose v boundaries are straight, λ 0, ε 0.01 at
/// 3840×2160, split aniso (tests/data/aniso_deep.toml). Its nodes split
/// 1:2, then 1:4, then 1:2 the other way: twelve rounds, where the node
/// memory had regions for the ten an iso split takes. At 898e7f6 depth
/// 10's children went over the ready scratch and past the buffer (`validate`:
/// GPU 145,111 ready nodes, oracle 181,915). Now both level kernels equal
/// the oracle and the CPU twin; and with the regions planted back at ten,
/// the kernels drop what has no region and refuse the frame in a sentence.
#[test]
fn aniso_nodes_split_beyond_l_max_rounds_stay_in_their_regions() {
    let gpu = gpu();
    let path = common::repo_path("tests/data/aniso_deep.toml");
    let s = bezier_subdiv::scene::desc::Scene::load(&path).unwrap();
    let geo = s.geometry().unwrap();
    let size = (3840, 2160);
    let mut v = view(&s.camera, size, 0.01, 0.0);
    v.params.flags |= FLAG_ANISO;
    let mut lists = Vec::new();
    for method in ["subdiv-indirect", "subdiv"] {
        let mut r = common::renderer(&gpu, &geo, method, size, options(|_| {}));
        let run = check_canonical(&mut r, &geo, &v, method);
        let vp = r.effective_params(&v);
        let plan = LevelPlan {
            chunk: run.own("chunk_nodes") as u32,
            levels: levels_for(true),
        };
        let twin = canonical_ready(
            &geo.patches,
            &geo.weights,
            &geo.flags,
            &r.scene().instance_records,
            &vp,
            plan,
        );
        let deepest = twin.nodes_per_depth.iter().rposition(|&n| n > 0).unwrap();
        println!(
            "{method}: {} ready nodes, rounds of splits to depth {deepest}, nodes per depth {:?}",
            run.stats.ready_quads, twin.nodes_per_depth
        );
        assert!(
            deepest as u32 > L_MAX,
            "{method}: the case must split more than l_max rounds deep"
        );
        assert_eq!(twin.dropped, 0);
        lists.push(run.ready);

        // The planted fault: regions for iso splits only.
        let o = options(|o| o.per_method.levels.planted_levels = Some(L_MAX));
        let mut planted = common::renderer(&gpu, &geo, method, size, o);
        let e = match planted.render(&v) {
            Ok(_) => panic!("{method}: the planted fault went unnoticed"),
            Err(e) => e.to_string(),
        };
        assert!(
            e.contains("deeper than the node memory has regions for"),
            "{method}: {e}"
        );
        let short = canonical_ready(
            &geo.patches,
            &geo.weights,
            &geo.flags,
            &r.scene().instance_records,
            &vp,
            LevelPlan {
                levels: L_MAX,
                ..plan
            },
        );
        assert!(short.dropped > 0, "the twin drops what the kernels drop");
    }
    assert_eq!(lists[0], lists[1], "the two level methods differ");
    gpu.finish();
}

/// Launched far beyond lavapipe's 8 threads: the occupancy discovery keeps
/// the ones running at once and the rest leave, so the barrier never waits
/// for a workgroup that cannot start.
#[test]
fn workgroups_beyond_the_resident_ones_leave() {
    let gpu = gpu();
    let (s, geo) = common::scene("kitchen.toml");
    let size = (320, 180);
    let o = options(|o| o.per_method.subdiv.groups = Some(64));
    let mut r = common::renderer(&gpu, &geo, "subdiv", size, o);
    let v = view(&s.camera, size, 1.0, 0.5);
    let run = check_canonical(&mut r, &geo, &v, "64 groups");
    assert_eq!(run.kernel(), "levels");
    let joined = run.own("workgroups_joined");
    println!("64 launched on 8 threads: {joined} joined");
    assert!((1..=8).contains(&joined), "{joined} joined");
    gpu.finish();
}

/// In the spout's mouth the nearest patches go below depth 6; with a node
/// memory of a few blocks per round every depth is taken in parts, by both
/// kernels, in the memory given (a budget that is a multiple of nothing:
/// the old per-depth kernel skipped the block straddling such a budget and
/// read slots nobody wrote).
#[test]
fn depths_too_large_for_one_chunk_are_taken_in_parts_at_any_depth() {
    let gpu = gpu();
    let (s, geo) = common::scene("teapot.toml");
    let size = (640, 360);
    let inside = Camera {
        position: [3.2, 0.0, 2.3],
        target: [-2.0, 0.0, 1.0],
        near: 0.001,
        ..s.camera
    };
    let v = view(&inside, size, 0.5, 0.5);
    let budget = 100_003;
    for method in ["subdiv-indirect", "subdiv"] {
        let o = options(|o| o.per_method.levels.node_memory = budget);
        let mut r = common::renderer(&gpu, &geo, method, size, o);
        let run = check_canonical(&mut r, &geo, &v, method);
        let memory = r.method().memory();
        let node_memory = memory.iter().find(|(k, _)| *k == "node_memory").unwrap().1;
        println!(
            "{method}: depth {}, {} rounds ({} in parts of {} nodes), {node_memory} bytes of \
             node memory, {} dispatches, redone {}",
            run.stats.max_depth,
            run.own("rounds"),
            run.own("rounds_split"),
            run.own("chunk_nodes"),
            run.own("dispatches"),
            run.report.redone
        );
        assert!(run.stats.max_depth > 6, "the view must go below depth 6");
        assert!(
            run.own("rounds_split") > 0,
            "some depth must take several rounds"
        );
        assert!(node_memory <= budget, "{node_memory} bytes");
        assert_eq!(run.own("node_memory_bytes"), node_memory);
        if method == "subdiv-indirect" {
            // The base rounds ran short: drawn again with twice as many and
            // a margin of two; the next frame records what this one needed
            // and two, the one after that and one.
            assert!(run.report.redone > 0, "the base rounds were enough");
            let needed = run.own("rounds");
            for margin in [2, 1] {
                let again = check_canonical(&mut r, &geo, &v, "again");
                assert_eq!(again.report.redone, 0);
                assert_eq!(again.own("rounds"), needed);
                assert_eq!(again.own("rounds_recorded"), needed + margin);
            }
        }
    }
    // The paper's depth limit is still there on request.
    let o = options(|o| o.per_method.subdiv_indirect.max_depth = 6);
    let mut r = common::renderer(&gpu, &geo, "subdiv-indirect", size, o);
    let run = check_canonical(&mut r, &geo, &v, "max depth 6");
    assert_eq!(run.stats.max_depth, 6);
    assert!(run.stats.nodes_at_lmax > 0);
    gpu.finish();
}

/// subdiv-indirect records the rounds a frame needs (issue 36: on the
/// kitchen's frame 0 at 1920x1080 it recorded 12 where 6 do): its first
/// frame takes one round per depth and the final copy, every later frame
/// of the view what the last one needed and one more, so the frame's
/// dispatches are its rounds, the first step and that one.
#[test]
fn per_depth_rounds_record_what_the_frame_needs() {
    let gpu = gpu();
    let (s, geo) = common::scene("kitchen.toml");
    let size = (1920, 1080);
    let v = view(&s.frame_camera(0).unwrap(), size, 1.0, 0.5);
    let mut r = common::renderer(&gpu, &geo, "subdiv-indirect", size, options(|_| {}));
    let first = check_canonical(&mut r, &geo, &v, "first frame");
    assert_eq!(first.own("rounds_recorded"), u64::from(L_MAX + 2));
    let second = check_canonical(&mut r, &geo, &v, "second frame");
    let needed = second.own("rounds");
    println!(
        "kitchen frame 0, 1920x1080: {needed} rounds, {} recorded, {} dispatches",
        second.own("rounds_recorded"),
        second.own("dispatches")
    );
    assert_eq!(needed, first.own("rounds"));
    assert_eq!(second.own("rounds_recorded"), needed + 1);
    assert_eq!(second.own("dispatches"), needed + 2);
    gpu.finish();
}

/// Whole instances outside the frustum are culled before depth 0 (kitchen
/// keyframe 2, low in the aisle: most of the room is behind the camera),
/// with depth 0 taken in many chunks (a small node memory): both level
/// kernels still write the oracle's set in the CPU twin's order, which
/// lists depth 0 from the same instance boxes, and the culled instances'
/// patches count as culled, never processed.
#[test]
fn instances_outside_the_frustum_are_culled_whole() {
    let gpu = gpu();
    let (s, geo) = common::scene("kitchen.toml");
    let size = (320, 180);
    let v = view(&s.frame_camera(2).unwrap(), size, 1.0, 0.5);
    for (method, budget) in [("subdiv-indirect", 200_000), ("subdiv", 300_001)] {
        let o = options(|o| o.per_method.levels.node_memory = budget);
        let mut r = common::renderer(&gpu, &geo, method, size, o);
        let run = check_canonical(&mut r, &geo, &v, method);
        let (culled, patches) = (
            run.own("instances_culled"),
            run.own("instance_culled_patches"),
        );
        println!(
            "{method}: {culled} instances ({patches} patches) culled whole, {} drawn; \
             {} rounds ({} in parts of {} nodes)",
            run.own("instances_drawn"),
            run.own("rounds"),
            run.own("rounds_split"),
            run.own("chunk_nodes")
        );
        assert!(culled > 100 && patches > 10_000, "{culled} {patches}");
        assert!(run.own("chunk_nodes") < 4_000, "depth 0 must span chunks");
    }
    gpu.finish();
}

/// A participant that never arrives (planted): the watchdog trips, the
/// frame is drawn again with the per-depth rounds and the stats say so, and
/// the method stays there.
#[test]
fn a_tripped_watchdog_sends_the_frame_to_the_per_depth_rounds() {
    let gpu = gpu();
    let (s, geo) = common::scene("teapot.toml");
    let size = (320, 180);
    let o = options(|o| {
        o.per_method.subdiv.level_faults = FAULT_PHANTOM;
        o.per_method.subdiv.watchdog_polls = 1 << 12;
    });
    let mut r = common::renderer(&gpu, &geo, "subdiv", size, o);
    let v = view(&s.camera, size, 1.0, 0.5);
    let start = std::time::Instant::now();
    let first = check_canonical(&mut r, &geo, &v, "phantom participant");
    println!(
        "watchdog and fallback in {:.2} s: {:?}",
        start.elapsed().as_secs_f64(),
        first
            .report
            .stats
            .own
            .iter()
            .find(|(k, _)| *k == "fallback")
    );
    assert_eq!(first.kernel(), "per-depth (fallback)");
    assert_eq!(first.report.redone, 1);
    let second = check_canonical(&mut r, &geo, &v, "after the fallback");
    assert_eq!(second.kernel(), "per-depth (fallback)");
    assert_eq!(second.report.redone, 0);
    gpu.finish();
}

/// Without the occupancy discovery (planted: every launched workgroup
/// joins), 64 workgroups on 8 threads deadlock at the first barrier: the
/// watchdog catches it and the frame still comes out right.
#[test]
fn without_discovery_more_workgroups_than_threads_deadlock_into_the_watchdog() {
    let gpu = gpu();
    let (s, geo) = common::scene("teapot.toml");
    let size = (320, 180);
    let o = options(|o| {
        o.per_method.subdiv.groups = Some(64);
        o.per_method.subdiv.level_faults = FAULT_NO_DISCOVERY;
        o.per_method.subdiv.watchdog_polls = 1 << 12;
    });
    let mut r = common::renderer(&gpu, &geo, "subdiv", size, o);
    let v = view(&s.camera, size, 1.0, 0.5);
    let run = check_canonical(&mut r, &geo, &v, "no discovery");
    assert_eq!(run.kernel(), "per-depth (fallback)");
    gpu.finish();
}

#[test]
fn workgroup_and_in_flight_limits_are_refused_with_a_sentence() {
    let gpu = gpu();
    let (s, geo) = common::scene("teapot.toml");
    let size = (320, 180);
    let max = gpu.info().limits.max_compute_work_group_count[0];
    for kernel in [Kernel::Levels, Kernel::Queue] {
        let o = options(|o| {
            o.per_method.subdiv.kernel = kernel;
            o.per_method.subdiv.groups = Some(max + 1);
        });
        let err = bezier_subdiv::renderer::Renderer::new(
            gpu.arc(),
            &geo,
            &bezier_subdiv::scene::geometry::SceneShading::from_geometry(&geo.patches),
            "subdiv",
            bezier_subdiv::renderer::RendererOptions {
                size,
                background: [0.1, 0.1, 0.1, 1.0],
                frames_in_flight: 2,
                methods: o,
            },
        )
        .err()
        .expect("too many workgroups must be refused");
        let msg = err.to_string();
        println!("{msg}");
        assert!(msg.contains("maxComputeWorkGroupCount"), "{msg}");
    }
    // 8192 workgroups x 2048 deque entries alone pass the 24-bit count.
    let o = options(|o| {
        o.per_method.subdiv.kernel = Kernel::Queue;
        o.per_method.subdiv.groups = Some(8192);
    });
    let mut r = common::renderer(&gpu, &geo, "subdiv", size, o);
    let err = r.render(&view(&s.camera, size, 1.0, 0.5)).unwrap_err();
    let msg = err.to_string();
    println!("{msg}");
    assert!(
        msg.contains("in flight") && msg.contains("--groups"),
        "{msg}"
    );
    gpu.finish();
}

fn queue(f: impl FnOnce(&mut MethodOptions)) -> MethodOptions {
    options(|o| {
        o.per_method.subdiv.kernel = Kernel::Queue;
        f(o)
    })
}

#[test]
fn queue_kernel_equals_the_oracle() {
    let gpu = gpu();
    for (name, size) in [("teapot.toml", (640, 360)), ("kitchen.toml", (320, 180))] {
        let (s, geo) = common::scene(name);
        let o = queue(|o| o.per_method.subdiv.groups = Some(8));
        let mut r = common::renderer(&gpu, &geo, "subdiv", size, o);
        for frame in 0..s.frame_count().min(2) {
            let cam = s.frame_camera(frame).unwrap();
            for (eps, lambda) in [(1.0, 0.5), (0.5, 0.0)] {
                let v = view(&cam, size, eps, lambda);
                let run = run_gpu(&mut r, &v).unwrap();
                check_against_oracle(&r, &geo, &v, &run);
                assert_eq!(run.kernel(), "queue");
                let st = run.stats;
                println!(
                    "{name} frame {frame} eps {eps} lambda {lambda}: {} ready, depth {}, queue \
                     pushed {} peak {} spills {}, atomics/node {:.4}",
                    st.ready_quads,
                    st.max_depth,
                    st.queue_pushed,
                    st.queue_peak_items,
                    st.queue_spills,
                    f64::from(st.global_atomics) / f64::from(st.nodes_processed)
                );
            }
        }
    }
    gpu.finish();
}

#[test]
fn tiny_queue_terminates_with_the_same_result() {
    let gpu = gpu();
    let (s, geo) = common::scene("teapot.toml");
    let mut v = view(&s.camera, (640, 360), 0.5, 0.5);
    // Donate on every split so a queue of a few dozen entries overflows.
    v.params.flags |= FLAG_QUEUE_STRESS;
    let mut spills = Vec::new();
    for capacity in [32, 65536] {
        let o = queue(|o| o.per_method.subdiv.queue_capacity = capacity);
        let mut r = common::renderer(&gpu, &geo, "subdiv", (640, 360), o);
        let run = run_gpu(&mut r, &v).unwrap();
        check_against_oracle(&r, &geo, &v, &run);
        let st = run.stats;
        println!(
            "queue of {capacity} (stressed): pushed {}, peak {}, spills {}",
            st.queue_pushed, st.queue_peak_items, st.queue_spills
        );
        assert!(st.queue_peak_items <= capacity);
        assert!(
            st.queue_pushed >= capacity.min(101),
            "the stress mode must use the queue"
        );
        spills.push(st.queue_spills);
    }
    assert!(spills[0] > 0, "a full queue must have refused donations");
    gpu.finish();
}

/// Every workgroup starts with its deque one slot from full (a first claim
/// of capacity − 1 base patches): it must take no split whose children it
/// cannot hold (a7d19dc took one whenever fewer than 3 slots were free),
/// donate instead, and end with the oracle's result.
#[test]
fn a_deque_one_slot_from_full_takes_no_split_it_cannot_hold() {
    let gpu = gpu();
    let (s, geo) = common::scene("kitchen.toml");
    let size = (640, 360);
    let o = queue(|o| {
        o.per_method.subdiv.groups = Some(8);
        o.per_method.subdiv.base_batch = SUBDIV_LOCAL_CAP - 1;
    });
    let mut r = common::renderer(&gpu, &geo, "subdiv", size, o);
    let v = view(&s.camera, size, 0.5, 0.5);
    let run = run_gpu(&mut r, &v).unwrap();
    check_against_oracle(&r, &geo, &v, &run);
    println!(
        "deque of {SUBDIV_LOCAL_CAP} started one slot from full: pushed {}, spills {}",
        run.stats.queue_pushed, run.stats.queue_spills
    );
    assert!(
        run.stats.queue_pushed > 0,
        "the full deques must have donated"
    );
    gpu.finish();
}

/// A phantom item in flight that never completes (planted): the queue
/// kernel gives up at its iteration cap and the frame is drawn with the
/// per-depth rounds, the oracle's result.
#[test]
fn planted_endless_loop_falls_back_to_the_per_depth_rounds() {
    let gpu = gpu();
    let (s, geo) = common::scene("teapot.toml");
    let o = queue(|o| {
        o.per_method.subdiv.plant_endless_loop = true;
        o.per_method.subdiv.idle_poll_cap = 1 << 14;
    });
    let mut r = common::renderer(&gpu, &geo, "subdiv", (320, 180), o);
    let v = view(&s.camera, (320, 180), 1.0, 0.5);
    let start = std::time::Instant::now();
    let run = run_gpu(&mut r, &v).unwrap();
    let reason = run.report.stats.own.iter().find(|(k, _)| *k == "fallback");
    println!(
        "planted loop caught after {:.2} s: {reason:?}",
        start.elapsed().as_secs_f64()
    );
    check_against_oracle(&r, &geo, &v, &run);
    assert_eq!(run.kernel(), "per-depth (fallback)");
    let reason = reason.unwrap().1.as_str().unwrap().to_string();
    assert!(
        reason.contains("iteration cap") && reason.contains("1 items still in flight"),
        "{reason}"
    );
    gpu.finish();
}
