//! The persistent subdivision kernel against the CPU oracle (lavapipe,
//! validation on): identical ready sets, termination with a tiny queue, and
//! the iteration cap catching a planted endless loop.

mod common;

use std::path::Path;

use bezier_subdiv::constants::*;
use bezier_subdiv::gpu::{Capacities, FrameGpu, SceneGpu, SceneLayout};
use bezier_subdiv::methods::subdiv::{GpuSubdivStats, Subdivider};
use bezier_subdiv::patch::oracle::{subdivide, triangle_counts};
use bezier_subdiv::patch::quadnode::QuadNode;
use bezier_subdiv::patch::view::ViewParams;
use bezier_subdiv::scene::file::{Scene, SceneGeometry};
use bezier_subdiv::vk::Context;

fn scene(name: &str) -> (Scene, SceneGeometry) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let s = Scene::load(&path).unwrap();
    let g = s.geometry().unwrap();
    (s, g)
}

struct Run {
    ready: Vec<QuadNode>,
    stats: GpuSubdivStats,
}

fn run_gpu(
    ctx: &Context,
    geo: &SceneGeometry,
    vp: &ViewParams,
    caps: Capacities,
    plant: bool,
    idle_poll_cap: Option<u32>,
) -> Run {
    let layout = SceneLayout::new(ctx).unwrap();
    let scene = SceneGpu::upload(ctx, &geo.patches, &geo.flags).unwrap();
    let mut frame = FrameGpu::new(ctx, &layout, &scene, caps).unwrap();
    frame.set_view(ctx, vp).unwrap();
    let mut sub = Subdivider::new(ctx, &layout, None).unwrap();
    if let Some(cap) = idle_poll_cap {
        sub.idle_poll_cap = cap;
    }
    sub.plant_endless_loop = plant;
    ctx.one_shot(|cmd| sub.record(ctx, cmd, &layout, &scene, &frame, None))
        .unwrap()
        .unwrap();
    let counters = frame.read_counters(ctx).unwrap();
    let stats = GpuSubdivStats::from_counters(&counters);
    let mut ready = frame.read_ready(ctx, stats.ready_quads).unwrap();
    ready.sort();
    Run { ready, stats }
}

fn check_against_oracle(
    ctx: &Context,
    geo: &SceneGeometry,
    vp: &ViewParams,
    caps: Capacities,
) -> GpuSubdivStats {
    let run = run_gpu(ctx, geo, vp, caps, false, None);
    assert_eq!(run.stats.errors, 0, "{:?}", run.stats.error_message());
    let oracle = subdivide(&geo.patches, &geo.flags, vp);
    let mut want = oracle.ready.clone();
    want.sort();
    assert_eq!(run.ready.len(), want.len(), "ready count GPU vs oracle");
    assert!(run.ready == want, "ready sets differ");
    let s = oracle.stats;
    let (tris, wedges) = triangle_counts(&oracle.ready, vp.flags & FLAG_WEDGES != 0);
    let g = run.stats;
    assert_eq!(
        (
            g.nodes_processed as u64,
            g.culled_patches as u64,
            g.backface_culled as u64
        ),
        (s.nodes_processed, s.culled_patches, s.backface_culled)
    );
    assert_eq!(
        (g.max_depth, g.nodes_at_lmax as u64),
        (s.max_depth, s.nodes_at_lmax)
    );
    assert_eq!(
        (g.triangles as u64, g.wedge_triangles as u64),
        (tris, wedges)
    );
    assert_eq!(g.in_flight_left, 0);
    // The indirect arguments describe exactly the ready list.
    let counters = g;
    let _ = counters;
    run.stats
}

#[test]
fn ready_set_equals_oracle_on_teapot_and_kitchen() {
    let gpu = common::gpu();
    for (name, size) in [("teapot.toml", (640, 360)), ("kitchen.toml", (320, 180))] {
        let (s, geo) = scene(name);
        for frame in 0..s.frame_count().min(3) {
            let cam = s.frame_camera(frame).unwrap();
            for (eps, lambda) in [(1.0, 0.5), (0.5, 0.0), (2.0, 1.0)] {
                let vp = cam.view_params(size.0, size.1, eps, lambda);
                let st = check_against_oracle(&gpu, &geo, &vp, Capacities::default());
                println!(
                    "{name} frame {frame} eps {eps} lambda {lambda}: {} ready, depth {}, queue pushed {} peak {} spills {}",
                    st.ready_quads, st.max_depth, st.queue_pushed, st.queue_peak_items, st.queue_spills
                );
            }
        }
    }
    gpu.finish();
}

#[test]
fn tiny_queue_terminates_with_the_same_result() {
    let gpu = common::gpu();
    let (s, geo) = scene("teapot.toml");
    let mut vp = s.camera.view_params(640, 360, 0.5, 0.5);
    // Donate on every split so a queue of a few dozen entries overflows.
    vp.flags |= FLAG_QUEUE_STRESS;
    let mut spills = Vec::new();
    for queue in [24, 65536] {
        let caps = Capacities {
            queue,
            ..Capacities::default()
        };
        let st = check_against_oracle(&gpu, &geo, &vp, caps);
        println!(
            "queue of {queue} (stressed): pushed {}, peak {}, spills {}",
            st.queue_pushed, st.queue_peak_items, st.queue_spills
        );
        assert!(st.queue_peak_items <= queue);
        assert!(st.queue_pushed > 100, "the stress mode must use the queue");
        spills.push(st.queue_spills);
    }
    assert!(spills[0] > 0, "a full queue must have refused donations");
    gpu.finish();
}

#[test]
fn planted_endless_loop_hits_the_iteration_cap() {
    let gpu = common::gpu();
    let (s, geo) = scene("teapot.toml");
    let vp = s.camera.view_params(320, 180, 1.0, 0.5);
    let start = std::time::Instant::now();
    let run = run_gpu(&gpu, &geo, &vp, Capacities::default(), true, None);
    println!(
        "planted loop caught after {:.2} s",
        start.elapsed().as_secs_f64()
    );
    assert_ne!(run.stats.errors & ERR_ITERATION_CAP, 0, "{:?}", run.stats);
    assert_eq!(run.stats.in_flight_left, 1);
    println!("planted loop: {}", run.stats.error_message().unwrap());
    gpu.finish();
}
