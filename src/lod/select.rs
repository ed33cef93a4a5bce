//! Which level draws each instance: the coarsest whose measured error,
//! scaled by the instance and projected at the instance's nearest depth,
//! is within ε pixels and whose shading, seen at that distance, is within
//! the shading bound, with hysteresis so an instance near a threshold does
//! not switch every frame.

use glam::{Vec3, Vec4};

use super::SceneLevels;
use crate::patch::view::ViewParams;
use crate::scene::instances::Instance;

/// A coarser level is entered only when its projected error is at most
/// this fraction of ε, and its shading error within the bound at this
/// fraction of the instance's footprint; a level is left (for a finer one)
/// as soon as either fails at the whole. Between the two an instance keeps
/// what it has, and neither bound is ever exceeded. An instance seen for the first time (no level chosen
/// before, or ε changed) takes the coarsest level within ε.
pub const ENTER: f32 = 0.8;

/// What draws an instance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Draw {
    /// Its patches, by the method.
    #[default]
    Patches,
    /// Level `.1` of model `.0` (indices into [`SceneLevels::models`] and
    /// its levels).
    Level(usize, usize),
}

/// The world-space size of one pixel times ε at the nearest depth of
/// `inst`'s box (`view.eps_k` × that depth), or `None` when some of the
/// box lies nearer than the near plane (an instance around the camera is
/// never coarsened).
pub fn allowed_error(view: &ViewParams, inst: &Instance) -> Option<f32> {
    let (lo, hi) = (Vec3::from_slice(&inst.lo), Vec3::from_slice(&inst.hi));
    if !lo.is_finite() || !hi.is_finite() || lo.x <= -f32::MAX {
        return None;
    }
    let r = view.depth_row;
    // The affine depth's minimum over the box: each term at its smaller end.
    let depth = |a: f32, l: f32, h: f32| (a * l).min(a * h);
    let z = depth(r.x, lo.x, hi.x) + depth(r.y, lo.y, hi.y) + depth(r.z, lo.z, hi.z) + r.w;
    (z > view.near).then_some(view.eps_k * z)
}

/// The side, in world units, of the footprint FLIP's filter averages
/// ([`super::shading::footprint_pixels`]) at the depth `allowed` was
/// found for ([`allowed_error`]; a pixel there is `allowed` / ε).
pub fn footprint(view: &ViewParams, allowed: f32) -> f32 {
    let pixel = allowed * view.pixel_at_unit_depth() / view.eps_k;
    super::shading::footprint_pixels() * pixel
}

/// How much the instance's transform stretches a distance at most: the
/// largest singular value of its linear part, from power iteration on AᵀA
/// (exact at once for a rotation with uniform scale, AᵀA = s²I), raised by
/// 1 % for what the iteration has not converged, and never above the
/// Frobenius norm, which bounds it.
pub fn stretch(inst: &Instance) -> f32 {
    let a = glam::Mat3::from_cols_array_2d(&std::array::from_fn(|i| {
        std::array::from_fn(|j| inst.rows[i][j])
    }))
    .transpose();
    let frobenius = inst
        .rows
        .iter()
        .map(|r| Vec4::new(r[0], r[1], r[2], 0.0).length_squared())
        .sum::<f32>()
        .sqrt();
    let ata = a.transpose() * a;
    let mut x = Vec3::new(0.577, 0.577, 0.578);
    for _ in 0..16 {
        x = (ata * x).normalize_or_zero();
    }
    let top = x.dot(ata * x).max(0.0).sqrt();
    (top * 1.01).min(frobenius)
}

/// What draws `inst` in `view`, given what drew it last frame (`prev`;
/// `None`: nothing has been chosen for it yet).
pub fn choose(
    levels: &SceneLevels,
    view: &ViewParams,
    inst: &Instance,
    prev: Option<Draw>,
) -> Draw {
    let Some(m) = levels.model_of(inst.source) else {
        return Draw::Patches;
    };
    let model = &levels.models[m];
    let Some(allowed) = allowed_error(view, inst) else {
        return Draw::Patches;
    };
    let scale = stretch(inst);
    // In model units: the largest stretch makes it the smallest, the
    // footprint whose error is the largest.
    let footprint = footprint(view, allowed) / scale;
    // Within ε, and shaded near enough to the surface for a footprint of
    // `fraction` of the instance's.
    let fits = |k: usize, fraction: f32| {
        let l = &model.levels[k];
        l.error * scale <= fraction * allowed
            && l.shading_error(fraction * footprint) <= levels.most_normal_error
    };
    let coarsest_within =
        |fraction: f32| (0..model.levels.len()).rev().find(|&k| fits(k, fraction));
    let keep = coarsest_within(1.0);
    let enter = coarsest_within(ENTER);
    let level = |k: Option<usize>| k.map_or(Draw::Patches, |k| Draw::Level(m, k));
    match prev {
        None => level(keep),
        // Still within both bounds and no coarser level with room to
        // spare: stay.
        Some(Draw::Level(pm, p)) if pm == m && fits(p, 1.0) && enter.is_none_or(|e| p >= e) => {
            Draw::Level(pm, p)
        }
        Some(Draw::Patches) if enter.is_none() => Draw::Patches,
        Some(_) => level(enter),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lod::{mesh::shapes, ModelLevels};
    use glam::DMat4;

    fn scene() -> SceneLevels {
        scene_of(&shapes::ball(4), crate::lod::MOST_NORMAL_ERROR)
    }

    /// One model, `patches`, its levels kept and chosen under the shading
    /// bound `bound` (radians).
    fn scene_of(patches: &[crate::patch::bezier::BezierPatch], bound: f32) -> SceneLevels {
        let mut s = SceneLevels {
            most_normal_error: bound,
            ..Default::default()
        };
        s.models.push(ModelLevels {
            source: 0,
            count: patches.len() as u32,
            levels: crate::lod::model_levels(patches, &crate::lod::mesh::plain_uv, false, bound),
            none_because: None,
        });
        s.by_source.insert(0, 0);
        s
    }

    /// A view along -z from the origin with one pixel of 0.001 at depth 1.
    fn view() -> ViewParams {
        let mut v: ViewParams = bytemuck::Zeroable::zeroed();
        v.depth_row = Vec4::new(0.0, 0.0, -1.0, 0.0);
        v.near = 0.1;
        v.eps_k = 0.001;
        // ε = 1: a pixel of 0.001 at depth 1 (a focal length of 1 over
        // half of 2000 rows).
        v.height = 2000;
        v.clip[1] = Vec4::new(0.0, 1.0, 0.0, 0.0);
        v.clip[3] = Vec4::new(0.0, 0.0, -1.0, 0.0);
        v
    }

    fn ball_at(z: f64) -> Instance {
        let m = DMat4::from_translation(glam::DVec3::new(0.0, 0.0, -z));
        let t = Instance::new(&m, 0, 0, 96, 0);
        let world: Vec<_> = shapes::ball(4).iter().map(|p| t.patch(p)).collect();
        t.bounded(&world)
    }

    #[test]
    fn farther_instances_get_coarser_levels_within_eps() {
        let s = scene();
        let v = view();
        let mut last = -1i64;
        for z in [0.05, 1.0, 10.0, 100.0, 1000.0, 10_000.0] {
            let inst = ball_at(z);
            let d = choose(&s, &v, &inst, Some(Draw::Patches));
            let rank = match d {
                Draw::Patches => -1,
                Draw::Level(_, l) => {
                    let err = s.models[0].levels[l].error * stretch(&inst);
                    assert!(err <= allowed_error(&v, &inst).unwrap(), "z {z}");
                    l as i64
                }
            };
            assert!(rank >= last, "z {z}: {d:?}");
            last = rank;
        }
        assert_eq!(choose(&s, &v, &ball_at(0.05), None), Draw::Patches);
        assert_eq!(last as usize, s.models[0].levels.len() - 1);
    }

    /// The rounded box under a 3° shading bound: every level is farther
    /// than 3° from the surface up close, so where ε alone would take a
    /// level, the instance keeps its patches (or a finer level) until the
    /// footprint FLIP averages over has grown enough.
    #[test]
    fn a_level_shaded_too_far_up_close_waits_for_distance() {
        let bound = 3f32.to_radians();
        let s = scene_of(&shapes::rounded_box(4), bound);
        let levels = &s.models[0].levels;
        assert!(levels.len() >= 2, "{} levels", levels.len());
        let v = view();
        let (mut held_back, mut last) = (0, -1i64);
        for k in 0..60 {
            let z = 1.2f64.powi(k);
            let m = DMat4::from_translation(glam::DVec3::new(0.0, 0.0, -z));
            let patches = shapes::rounded_box(4);
            let t = Instance::new(&m, 0, 0, patches.len() as u32, 0);
            let world: Vec<_> = patches.iter().map(|p| t.patch(p)).collect();
            let inst = t.bounded(&world);
            let Some(allowed) = allowed_error(&v, &inst) else {
                continue;
            };
            let by_eps = levels.iter().rposition(|l| l.error <= allowed);
            let rank = match choose(&s, &v, &inst, None) {
                Draw::Patches => -1,
                Draw::Level(_, l) => {
                    let seen = levels[l].shading_error(footprint(&v, allowed));
                    assert!(seen <= bound, "z {z}: level {l} at {}°", seen.to_degrees());
                    l as i64
                }
            };
            held_back += usize::from(by_eps.map_or(-1, |e| e as i64) > rank);
            assert!(rank >= last, "z {z}");
            last = rank;
        }
        assert!(held_back > 0, "the shading bound never chose finer than ε");
        assert_eq!(last as usize, levels.len() - 1);
    }

    #[test]
    fn an_instance_near_a_threshold_keeps_its_level() {
        let s = scene();
        let v = view();
        let l0 = s.models[0].levels[0].error * stretch(&ball_at(1.0));
        // A depth where level 0 is within ε but not within ENTER·ε.
        let inst = (1..1000)
            .map(|k| ball_at(f64::from(l0 / v.eps_k) * (0.8 + k as f64 * 0.001)))
            .find(|t| {
                let a = allowed_error(&v, t).unwrap();
                l0 <= a && l0 > ENTER * a * 1.01
            })
            .expect("some depth lies in the band");
        assert_eq!(choose(&s, &v, &inst, Some(Draw::Patches)), Draw::Patches);
        assert_eq!(
            choose(&s, &v, &inst, Some(Draw::Level(0, 0))),
            Draw::Level(0, 0)
        );
        // Seen for the first time, it takes the level: ε is not exceeded.
        assert_eq!(choose(&s, &v, &inst, None), Draw::Level(0, 0));
    }
}
