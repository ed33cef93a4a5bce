//! The persistent subdivision kernel against the CPU oracle (lavapipe,
//! validation on): identical ready sets and counters, termination with a
//! tiny queue, and the iteration cap catching a planted endless loop.

mod common;

use bezier_subdiv::constants::*;
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::subdiv::GpuSubdivStats;
use bezier_subdiv::methods::{MethodOptions, RenderError};
use bezier_subdiv::patch::oracle::{subdivide, triangle_counts};
use bezier_subdiv::patch::quadnode::QuadNode;
use bezier_subdiv::renderer::Renderer;
use bezier_subdiv::scene::camera::Camera;
use bezier_subdiv::scene::file::SceneGeometry;

struct Run {
    ready: Vec<QuadNode>,
    stats: GpuSubdivStats,
}

fn view(cam: &Camera, size: (u32, u32), eps: f64, lambda: f64) -> View {
    View::new(cam, size, eps, lambda, SHADE_NORMAL)
}

/// Renders `v` and reads the ready list (sorted) and the raw counters.
fn run_gpu(r: &mut Renderer, v: &View) -> Result<Run, RenderError> {
    r.render(v)?;
    let ctx = r.context().clone();
    let list = r.method().ready().expect("subdiv has a ready list").list();
    let stats = GpuSubdivStats::from_counters(&list.read_counters(&ctx)?);
    let mut ready = list.read_ready(&ctx, stats.ready_quads)?;
    ready.sort();
    Ok(Run { ready, stats })
}

fn check_against_oracle(r: &mut Renderer, geo: &SceneGeometry, v: &View) -> GpuSubdivStats {
    let run = run_gpu(r, v).unwrap();
    assert_eq!(run.stats.errors, 0, "{:?}", run.stats.error_message());
    let vp = &v.params;
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
    run.stats
}

#[test]
fn ready_set_equals_oracle_on_teapot_and_kitchen() {
    let gpu = common::gpu();
    for (name, size) in [("teapot.toml", (640, 360)), ("kitchen.toml", (320, 180))] {
        let (s, geo) = common::scene(name);
        let mut r = common::renderer(
            &gpu,
            &geo,
            "subdiv",
            size,
            MethodOptions::new(DrawPath::Mesh),
        );
        for frame in 0..s.frame_count().min(3) {
            let cam = s.frame_camera(frame).unwrap();
            for (eps, lambda) in [(1.0, 0.5), (0.5, 0.0), (2.0, 1.0)] {
                let st = check_against_oracle(&mut r, &geo, &view(&cam, size, eps, lambda));
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
    let (s, geo) = common::scene("teapot.toml");
    let mut v = view(&s.camera, (640, 360), 0.5, 0.5);
    // Donate on every split so a queue of a few dozen entries overflows.
    v.params.flags |= FLAG_QUEUE_STRESS;
    let mut spills = Vec::new();
    for queue in [32, 65536] {
        let options = MethodOptions {
            queue_capacity: queue,
            ..MethodOptions::new(DrawPath::Mesh)
        };
        let mut r = common::renderer(&gpu, &geo, "subdiv", (640, 360), options);
        let st = check_against_oracle(&mut r, &geo, &v);
        println!(
            "queue of {queue} (stressed): pushed {}, peak {}, spills {}",
            st.queue_pushed, st.queue_peak_items, st.queue_spills
        );
        assert!(st.queue_peak_items <= queue);
        // The stress mode donates every item it can: the tiny queue fills,
        // the large one carries a good part of the tree.
        assert!(
            st.queue_pushed >= queue.min(101),
            "the stress mode must use the queue"
        );
        spills.push(st.queue_spills);
    }
    assert!(spills[0] > 0, "a full queue must have refused donations");
    gpu.finish();
}

#[test]
fn planted_endless_loop_hits_the_iteration_cap() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("teapot.toml");
    let options = MethodOptions {
        plant_endless_loop: true,
        ..MethodOptions::new(DrawPath::Mesh)
    };
    let mut r = common::renderer(&gpu, &geo, "subdiv", (320, 180), options);
    let start = std::time::Instant::now();
    let err = run_gpu(&mut r, &view(&s.camera, (320, 180), 1.0, 0.5))
        .err()
        .expect("a planted endless loop must fail the frame");
    println!(
        "planted loop caught after {:.2} s: {err}",
        start.elapsed().as_secs_f64()
    );
    let msg = err.to_string();
    assert!(
        matches!(
            err,
            RenderError::Method {
                method: "subdiv",
                ..
            }
        ),
        "{msg}"
    );
    assert!(
        msg.contains("iteration cap") && msg.contains("1 items still in flight"),
        "{msg}"
    );
    assert!(!msg.contains("invalid use"), "{msg}");
    // The counters say the same.
    let list = r.method().ready().unwrap().list();
    let st = GpuSubdivStats::from_counters(&list.read_counters(&gpu).unwrap());
    assert_ne!(st.errors & ERR_ITERATION_CAP, 0, "{st:?}");
    assert_eq!(st.in_flight_left, 1);
    gpu.finish();
}

/// subdiv-indirect stops at its depth limit exactly as the oracle does with
/// that limit, where the persistent kernel goes deeper; and a node budget
/// too small for a depth fails the frame with what it needed instead of
/// drawing it incomplete.
#[test]
fn per_depth_method_honours_its_limit_and_budget() {
    let gpu = common::gpu();
    let (s, geo) = common::scene("teapot.toml");
    let size = (640, 360);
    // In the spout's mouth: the nearest patches subdivide below depth 6.
    let inside = Camera {
        position: [3.2, 0.0, 2.3],
        target: [-2.0, 0.0, 1.0],
        near: 0.001,
        ..s.camera
    };
    let v = view(&inside, size, 0.5, 0.5);
    let mut persistent = common::renderer(
        &gpu,
        &geo,
        "subdiv",
        size,
        MethodOptions::new(DrawPath::Mesh),
    );
    let deep = check_against_oracle(&mut persistent, &geo, &v);
    assert!(
        deep.max_depth > 6,
        "the view must go below the limit: {deep:?}"
    );
    let mut r = common::renderer(
        &gpu,
        &geo,
        "subdiv-indirect",
        size,
        MethodOptions::new(DrawPath::Mesh),
    );
    let limited = View {
        params: r.effective_params(&v),
        ..v
    };
    assert_eq!(limited.params.l_max, 6);
    let st = check_against_oracle(&mut r, &geo, &limited);
    assert_eq!(st.max_depth, 6);
    assert!(st.nodes_at_lmax > 0);
    println!(
        "persistent: depth {}, {} ready; per-depth (limit 6): {} ready, {} at the limit",
        deep.max_depth, deep.ready_quads, st.ready_quads, st.nodes_at_lmax
    );

    let tight = MethodOptions {
        node_capacity: Some(100),
        ..MethodOptions::new(DrawPath::Mesh)
    };
    let mut r = common::renderer(&gpu, &geo, "subdiv-indirect", size, tight);
    let err = r
        .render(&v)
        .expect_err("a 100-node budget cannot hold the teapot");
    let msg = err.to_string();
    println!("{msg}");
    assert!(msg.contains("needs") && msg.contains("holds 100"), "{msg}");
    gpu.finish();
}
