//! Back-face culling checked against the triangles it removes.

use bezier_subdiv::patch::ops::{cross3, dot3};
use bezier_subdiv::patch::oracle::{Outcome, Triangle};
use bezier_subdiv::patch::quadnode::QuadNode;
use glam::Vec3;

/// Subdivides base patches `0..patches` with `process` and checks that
/// every triangle of each node it culls as back-facing (`triangulate`
/// gives them, wedges included) faces away from `eye`; `name` names the
/// model in a failure. Returns how many nodes were culled.
pub fn culled_face_away(
    name: &str,
    patches: u32,
    eye: Vec3,
    process: impl Fn(QuadNode) -> Outcome,
    triangulate: impl Fn(QuadNode) -> Vec<Triangle>,
) -> usize {
    let mut culled = 0;
    let mut stack: Vec<QuadNode> = (0..patches).map(QuadNode::root).collect();
    while let Some(q) = stack.pop() {
        match process(q) {
            Outcome::Split(ch) => stack.extend(ch),
            Outcome::BackFacing => {
                culled += 1;
                for t in triangulate(q) {
                    let n = cross3(t.v[1] - t.v[0], t.v[2] - t.v[0]);
                    assert!(
                        dot3(n, t.v[0] - eye) > 0.0,
                        "{name}: a culled triangle faces the eye: {t:?}"
                    );
                }
            }
            _ => {}
        }
    }
    culled
}
