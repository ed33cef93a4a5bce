//! Subdivision cages the conversion tests walk, and OBJ text edits.

use bezier_subdiv::cage::stencil::CageModel;
use glam::Vec3;

/// The shipped Catmull-Clark models, relative to the repository root.
const SHIPPED: &[&str] = &[
    "scenes/models/catmark_torus.obj",
    "scenes/models/catmark_cube.obj",
    "scenes/models/catmark_pawn.obj",
    "scenes/models/catmark_car.obj",
    "scenes/models/catmark_helmet.obj",
    "scenes/models/catmark_xord_interior.obj",
    "scenes/models/catmark_pole64.obj",
];

/// The tagged test cages (creases, semi-sharp edges, non-manifold parts).
const TAGGED: &[&str] = &[
    "tests/data/cages/grid_crease.obj",
    "tests/data/cages/grid_semi.obj",
    "tests/data/cages/book.obj",
    "tests/data/cages/cubes_touching.obj",
];

/// The shipped models, then `extra`, then the tagged test cages.
pub fn with(extra: &[&'static str]) -> Vec<&'static str> {
    SHIPPED.iter().chain(extra).chain(TAGGED).copied().collect()
}

/// `text` with the `v` line of each cage vertex replaced by its position
/// in `posed`.
pub fn with_positions(text: &str, cage: &CageModel, posed: &[Vec3]) -> String {
    let mut at: Vec<Option<Vec3>> = vec![None; cage.file_vertices];
    for (v, &i) in cage.file_vertex.iter().enumerate() {
        at[i] = Some(posed[v]);
    }
    let mut out = String::new();
    let mut k = 0;
    for line in text.lines() {
        let is_v = line.split_whitespace().next() == Some("v");
        match at.get(k).copied().flatten().filter(|_| is_v) {
            Some(p) => out += &format!("v {} {} {}\n", p.x, p.y, p.z),
            None => {
                out += line;
                out.push('\n');
            }
        }
        if is_v {
            k += 1;
        }
    }
    out
}
