//! Every model keeps its own tint in every draw path, the same as
//! `palette::model_tint` (the CPU preview's): the kitchen (12 models) at
//! 320×180, each pixel's patch read back (`SHADE_PATCH_ID`) and its unlit
//! tint (`SHADE_TINT`) compared with the model's. Before, the shaders
//! wrapped after eight models and the toy cars (model 8) took the floor's
//! orange.

mod common;

use std::collections::BTreeSet;

use bezier_subdiv::constants::{PATCH_MODEL_SHIFT, SHADE_PATCH_ID, SHADE_TINT};
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::palette::model_tint;

const SIZE: (u32, u32) = (320, 180);

#[test]
fn every_model_keeps_its_own_tint() {
    let gpu = common::gpu();
    let (scene, geo) = common::scene("kitchen.toml");
    let camera = scene.frame_camera(0).unwrap();
    let cases = [
        ("subdiv", DrawPath::Mesh),
        ("subdiv", DrawPath::Fallback),
        ("ground-truth", DrawPath::Mesh),
        ("tess", DrawPath::Mesh),
        ("cudatess", DrawPath::Mesh),
    ];
    for (method, draw) in cases {
        let mut options = MethodOptions::new(draw);
        options.per_method.ground_truth.grid = 8;
        let mut r = common::renderer(&gpu, &geo, method, SIZE, options);
        r.set_background([1.0; 4]);
        let mut image = |shade: u32| {
            r.render(&View::new(&camera, SIZE, 1.0, 0.5, shade))
                .unwrap();
            r.read_image().unwrap()
        };
        let ids = image(SHADE_PATCH_ID);
        let tints = image(SHADE_TINT);
        let mut models = BTreeSet::new();
        let mut wrong = 0;
        for (id, tint) in ids.chunks_exact(4).zip(tints.chunks_exact(4)) {
            let patch = (id[0] as usize) << 16 | (id[1] as usize) << 8 | id[2] as usize;
            let Some(flags) = geo.flags.get(patch) else {
                continue; // the background
            };
            let model = flags >> PATCH_MODEL_SHIFT;
            models.insert(model);
            let want = model_tint(model).map(|c| c * 255.0);
            if (0..3).any(|k| (f32::from(tint[k]) - want[k]).abs() > 1.0) {
                wrong += 1;
            }
        }
        println!("{method} ({draw:?}): models {models:?}, {wrong} pixels off their tint");
        assert!(
            models.iter().any(|&m| m >= 8),
            "{method}: the view must show a model past the eighth: {models:?}"
        );
        assert!(models.len() >= 10, "{method}: {models:?}");
        assert_eq!(
            wrong, 0,
            "{method} ({draw:?}): pixels off their model's tint"
        );
    }
    gpu.finish();
}
