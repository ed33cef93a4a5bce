//! `validate` end to end on lavapipe (validation layer on).

mod common;

use std::path::Path;

use bezier_subdiv::commands::validate::{run, ValidateArgs};
use bezier_subdiv::draw::DrawRequest;
use bezier_subdiv::vk::DeviceSelector;

fn args(scene: &str, draw: DrawRequest) -> ValidateArgs {
    ValidateArgs {
        scene: Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(scene),
        frame: None,
        method: "subdiv".into(),
        eps: None,
        lambda: None,
        size: (320, 180),
        draw,
        device: DeviceSelector::Auto,
        validation: true,
        skip_holes: false,
        debug_dir: Some(Path::new(env!("CARGO_MANIFEST_DIR")).join("target/test-output/holes")),
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

#[test]
fn kitchen_validates() {
    let _gpu = common::gpu();
    let mut a = args("kitchen.toml", DrawRequest::Auto);
    a.size = (320, 180);
    let report = run(&a).unwrap();
    println!("{}", report.table);
    assert!(report.ok(), "{}", report.table);
}
