//! The colours every image shares: the depth heat map's ramp (declared in
//! `src/constants.rs`, generated into the shaders' header) and the tint of
//! each model.
//!
//! The tint of each model, the same in every image: the GPU's lit shading
//! (`model_tint` in `glsl/common/shade.glsl`, its twin) and the CPU preview
//! (`validate::raster`). Colours are display values (what the UNORM target holds).
//!
//! The first eight are hand-picked; from the ninth on, hues step by the
//! golden ratio (so no hue comes back exactly, and consecutive models lie
//! far apart on the wheel) at three brightness levels. Before, the shaders
//! wrapped after eight (`& 7u`) and the kitchen's toy cars (model 8) took
//! the floor's orange.

/// The hand-picked tints of models 0..8.
pub const FIRST_TINTS: [[f32; 3]; 8] = [
    [0.90, 0.62, 0.38],
    [0.42, 0.62, 0.90],
    [0.52, 0.80, 0.45],
    [0.88, 0.46, 0.56],
    [0.80, 0.74, 0.46],
    [0.60, 0.55, 0.88],
    [0.42, 0.80, 0.78],
    [0.78, 0.78, 0.78],
];

/// Hue of model 8 before the golden-ratio steps, and the step.
const HUE_START: f32 = 0.425;
const HUE_STEP: f32 = 0.618_034;
/// Saturation and the three brightness levels of models from 8 on.
const SATURATION: f32 = 0.55;
const VALUES: [f32; 3] = [0.92, 0.78, 0.64];

/// The tint of model `index` (display values in 0..1).
pub fn model_tint(index: u32) -> [f32; 3] {
    if let Some(t) = FIRST_TINTS.get(index as usize) {
        return *t;
    }
    // f32 as in the shader; the fraction is taken of the step alone first
    // so large indices keep their precision.
    let h = fract(HUE_START + fract(HUE_STEP * (index % 4096) as f32));
    let v = VALUES[(index % 3) as usize];
    [1.0, 2.0 / 3.0, 1.0 / 3.0].map(|o| {
        let c = ((fract(h + o) * 6.0 - 3.0).abs() - 1.0).clamp(0.0, 1.0);
        v * ((1.0 - SATURATION) + SATURATION * c)
    })
}

/// The depth heat map's colour of `depth` (clamped to 10), RGB8 display
/// values: what `--shade depth` draws lit, and the window's legend.
pub fn depth_color(depth: u32) -> [u8; 3] {
    use crate::constants::*;
    let ramp = [
        DEPTH_RAMP_0,
        DEPTH_RAMP_1,
        DEPTH_RAMP_2,
        DEPTH_RAMP_3,
        DEPTH_RAMP_4,
        DEPTH_RAMP_5,
        DEPTH_RAMP_6,
        DEPTH_RAMP_7,
        DEPTH_RAMP_8,
        DEPTH_RAMP_9,
        DEPTH_RAMP_10,
    ];
    rgb8(ramp[depth.min(10) as usize])
}

/// The wedges' colour in the wedge view.
pub fn wedge_color() -> [u8; 3] {
    rgb8(crate::constants::WEDGE_RGB)
}

fn rgb8(c: u32) -> [u8; 3] {
    [(c >> 16) as u8, (c >> 8) as u8, c as u8]
}

fn fract(x: f32) -> f32 {
    x - x.floor()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn distance(a: [f32; 3], b: [f32; 3]) -> f32 {
        a.iter()
            .zip(&b)
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f32>()
            .sqrt()
    }

    /// No two of the first 48 models share a colour, and the first 24 are
    /// clearly apart (the kitchen has 12 models).
    #[test]
    fn tints_do_not_repeat() {
        let tints: Vec<[f32; 3]> = (0..48).map(model_tint).collect();
        for (i, a) in tints.iter().enumerate() {
            assert!(a.iter().all(|c| (0.0..=1.0).contains(c)), "{i}: {a:?}");
            for (j, b) in tints.iter().enumerate().skip(i + 1) {
                let d = distance(*a, *b);
                let least = if j < 24 { 0.1 } else { 0.02 };
                assert!(d > least, "models {i} and {j}: {a:?} {b:?} ({d})");
            }
        }
    }
}
