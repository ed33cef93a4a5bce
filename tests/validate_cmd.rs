//! `validate` end to end on lavapipe (validation layer on).

mod common;

use std::path::Path;

use bezier_subdiv::commands::validate::{run, ValidateArgs};
use bezier_subdiv::commands::GpuRequest;
use bezier_subdiv::draw::DrawRequest;

fn args(scene: &str, draw: DrawRequest) -> ValidateArgs {
    let mut gpu = GpuRequest::new(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(scene),
    );
    gpu.size = (320, 180);
    gpu.draw = draw;
    gpu.validation = true;
    ValidateArgs {
        gpu,
        frame: None,
        skip_holes: false,
        debug_dir: Some(common::output_dir("holes")),
    }
}

#[test]
fn teapot_validates_on_both_paths() {
    let _gpu = common::gpu();
    for draw in [DrawRequest::Mesh, DrawRequest::Fallback] {
        let report = run(&args("teapot.toml", draw)).unwrap();
        println!("{}", report.table);
        assert!(report.ok(), "{}", report.table);
    }
}

/// `validate --split aniso` on the teapot: the ready set, the positions,
/// the §4.4 reordering test and the hole test all hold for 1:2 splits, on
/// both paths.
#[test]
fn teapot_validates_with_aniso_splits() {
    let _gpu = common::gpu();
    for draw in [DrawRequest::Mesh, DrawRequest::Fallback] {
        let mut a = args("teapot.toml", draw);
        a.gpu.split = Some(bezier_subdiv::patch::view::Split::Aniso);
        let report = run(&a).unwrap();
        println!("{}", report.table);
        assert!(report.ok(), "{}", report.table);
        assert!(report.table.contains("split aniso"), "{}", report.table);
        let holes = report
            .results
            .iter()
            .filter(|r| r.check.starts_with("holes"))
            .count();
        assert_eq!(holes, 1, "{}", report.table);
    }
}

#[test]
fn kitchen_validates() {
    let _gpu = common::gpu();
    let a = args("kitchen.toml", DrawRequest::Auto);
    let report = run(&a).unwrap();
    println!("{}", report.table);
    assert!(report.ok(), "{}", report.table);
}

/// `validate --method ground-truth` runs the checks that apply: the hole
/// test on every model, nothing against the oracle.
#[test]
fn ground_truth_gets_the_hole_test() {
    let _gpu = common::gpu();
    let mut a = args("teapot.toml", DrawRequest::Auto);
    a.gpu.method = "ground-truth".into();
    a.gpu.grid = 16;
    let report = run(&a).unwrap();
    println!("{}", report.table);
    assert!(report.ok(), "{}", report.table);
    let checks: Vec<&str> = report.results.iter().map(|r| r.check.as_str()).collect();
    assert_eq!(checks, ["holes teapot.bpt", "validation layer"]);
    assert!(
        report.table.contains("method ground-truth, grid path"),
        "{}",
        report.table
    );
}
