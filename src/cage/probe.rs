//! Finding a conversion's stencils by probing it (`stencil`'s module doc
//! says why and how): the outputs named, the reach of each assumed, the
//! vertices coloured so far-apart ones share a run, the probe cages
//! converted, and each output's combination read off and checked.

use std::collections::HashMap;
use std::path::Path;

use glam::{DVec3, Vec3};

use super::acc::Conversion;
use super::linear::Comb;
use super::mesh::{Cage, Topology};
use super::tangent;
use crate::input::SceneError;

use super::stencil::CageStencils;

/// Where `acc.rs` puts a face's corner and edge points in its patch, face
/// (v0, v1, v2, v3): (slot, the corner's vertex k) and (slot, the edge
/// point's (near, far) corners). Only used to find most of the points the
/// shading construction reads among the patches' own (checked bit for bit
/// against the conversion; any other is probed as an output of its own).
const CORNER_SLOTS: [(usize, usize); 4] = [(0, 0), (3, 1), (15, 2), (12, 3)];
/// See [`CORNER_SLOTS`].
const EDGE_SLOTS: [(usize, (usize, usize)); 8] = [
    (1, (0, 1)),
    (2, (1, 0)),
    (4, (0, 3)),
    (7, (1, 2)),
    (8, (3, 0)),
    (11, (2, 1)),
    (13, (3, 2)),
    (14, (2, 3)),
];

/// Names of the conversion's outputs: every control point of every patch,
/// then the corner and edge points the shading construction reads that no
/// patch holds (next to holes).
struct Outputs {
    patches: usize,
    /// Corners and edge points of their own, after the patches' points.
    extra: Vec<Key>,
    corner_id: HashMap<usize, u32>,
    edge_id: HashMap<(usize, usize), u32>,
}

#[derive(Clone, Copy)]
enum Key {
    Corner(usize),
    Edge(usize, usize),
}

impl Outputs {
    fn new(cage: &Cage, fine: &Topology, conv: &Conversion) -> Self {
        let patches = conv.patches.len();
        let mut corner_id: HashMap<usize, u32> = HashMap::new();
        let mut edge_id: HashMap<(usize, usize), u32> = HashMap::new();
        for (p, &f) in conv.faces.iter().enumerate() {
            let face = &cage.faces[f];
            let pts = &conv.patches[p].pts;
            for (slot, k) in CORNER_SLOTS {
                let v = face[k];
                if pts[slot].to_array().map(f32::to_bits)
                    == conv.corner[v].to_array().map(f32::to_bits)
                {
                    corner_id.entry(v).or_insert((16 * p + slot) as u32);
                }
            }
            for (slot, (a, b)) in EDGE_SLOTS {
                let e = (face[a], face[b]);
                let same = conv.edge_point.get(&e).is_some_and(|q| {
                    q.to_array().map(f32::to_bits) == pts[slot].to_array().map(f32::to_bits)
                });
                if same {
                    edge_id.entry(e).or_insert((16 * p + slot) as u32);
                }
            }
        }
        let mut extra = Vec::new();
        for v in 0..conv.corner.len() {
            if !fine.fans[v].is_empty() && !corner_id.contains_key(&v) {
                corner_id.insert(v, (16 * patches + extra.len()) as u32);
                extra.push(Key::Corner(v));
            }
        }
        let mut edges: Vec<(usize, usize)> = conv.edge_point.keys().copied().collect();
        edges.sort_unstable();
        for e in edges {
            if let std::collections::hash_map::Entry::Vacant(slot) = edge_id.entry(e) {
                slot.insert((16 * patches + extra.len()) as u32);
                extra.push(Key::Edge(e.0, e.1));
            }
        }
        Outputs {
            patches,
            extra,
            corner_id,
            edge_id,
        }
    }

    fn len(&self) -> usize {
        16 * self.patches + self.extra.len()
    }

    fn values(&self, conv: &Conversion) -> Vec<Vec3> {
        let mut out: Vec<Vec3> = conv.patches.iter().flat_map(|p| p.pts).collect();
        out.extend(self.extra.iter().map(|&k| match k {
            Key::Corner(v) => conv.corner[v],
            Key::Edge(a, b) => conv.edge_point[&(a, b)],
        }));
        out
    }

    /// The fine faces output `id` belongs to.
    fn faces(&self, id: usize, fine: &Topology, conv: &Conversion) -> Vec<usize> {
        if id < 16 * self.patches {
            return vec![conv.faces[id / 16]];
        }
        let fan_faces = |v: usize| -> Vec<usize> {
            fine.fans[v]
                .iter()
                .flat_map(|f| f.corners.iter().map(|c| c.0))
                .collect()
        };
        match self.extra[id - 16 * self.patches] {
            Key::Corner(v) => fan_faces(v),
            Key::Edge(a, b) => match fine.edge_id(a, b) {
                Some(e) => fine.edges[e].uses.iter().map(|u| u.0).collect(),
                None => fan_faces(a),
            },
        }
    }
}

/// The cage vertices within `rings` face rings of each face of `cage`
/// (faces sharing a vertex are one ring apart), sorted.
fn reach(cage: &Cage, topo: &Topology, rings: u32) -> Vec<Vec<u32>> {
    let faces_of = |v: usize| -> Vec<usize> {
        topo.fans[v]
            .iter()
            .flat_map(|f| f.corners.iter().map(|c| c.0))
            .collect()
    };
    let mut vertex_faces: Vec<Vec<usize>> = (0..cage.positions.len()).map(faces_of).collect();
    for (f, face) in cage.faces.iter().enumerate() {
        for &v in face {
            if !vertex_faces[v].contains(&f) {
                vertex_faces[v].push(f);
            }
        }
    }
    (0..cage.faces.len())
        .map(|f| {
            let mut faces = vec![f];
            let mut seen = std::collections::HashSet::from([f]);
            let mut frontier = vec![f];
            for _ in 0..rings {
                let mut next = Vec::new();
                for &g in &frontier {
                    for &v in &cage.faces[g] {
                        for &h in &vertex_faces[v] {
                            if seen.insert(h) {
                                next.push(h);
                                faces.push(h);
                            }
                        }
                    }
                }
                frontier = next;
            }
            let mut vs: Vec<u32> = faces
                .iter()
                .flat_map(|&g| cage.faces[g].iter().map(|&v| v as u32))
                .collect();
            vs.sort_unstable();
            vs.dedup();
            vs
        })
        .collect()
}

/// A colouring of the vertices such that no two vertices of one candidate
/// set share a colour (DSATUR: the next vertex is the one with the most
/// distinct colours among its neighbours); returns the colours and their
/// number.
fn colour(vertices: usize, sets: &[Vec<u32>]) -> (Vec<u32>, u32) {
    let mut member: Vec<Vec<u32>> = vec![Vec::new(); vertices];
    for (s, set) in sets.iter().enumerate() {
        for &v in set {
            member[v as usize].push(s as u32);
        }
    }
    // Neighbours: the vertices sharing a set.
    let neighbours: Vec<Vec<u32>> = (0..vertices)
        .map(|v| {
            let mut n: Vec<u32> = member[v]
                .iter()
                .flat_map(|&s| sets[s as usize].iter().copied())
                .filter(|&u| u as usize != v)
                .collect();
            n.sort_unstable();
            n.dedup();
            n
        })
        .collect();
    let mut colour = vec![u32::MAX; vertices];
    // Per vertex, the colours its coloured neighbours have (sorted).
    let mut seen: Vec<Vec<u32>> = vec![Vec::new(); vertices];
    let mut heap: std::collections::BinaryHeap<(usize, usize, std::cmp::Reverse<usize>)> = (0
        ..vertices)
        .filter(|&v| !member[v].is_empty())
        .map(|v| (0, neighbours[v].len(), std::cmp::Reverse(v)))
        .collect();
    let mut count = 0;
    while let Some((sat, _, std::cmp::Reverse(v))) = heap.pop() {
        if colour[v] != u32::MAX || sat != seen[v].len() {
            continue;
        }
        let c = (0u32..)
            .find(|c| seen[v].binary_search(c).is_err())
            .unwrap_or(0);
        colour[v] = c;
        count = count.max(c + 1);
        for &u in &neighbours[v] {
            let u = u as usize;
            if colour[u] == u32::MAX {
                if let Err(at) = seen[u].binary_search(&c) {
                    seen[u].insert(at, c);
                    heap.push((seen[u].len(), neighbours[u].len(), std::cmp::Reverse(u)));
                }
            }
        }
    }
    (colour, count)
}

/// The conversion's part that is linear in the cage: given a cage with the
/// topology and tags of the one converted, its conversion.
pub type Linear<'a> = dyn Fn(&Cage) -> Result<Conversion, SceneError> + Sync + 'a;

/// Face rings the probing assumes an output may reach at first; each
/// failed check adds one, up to [`MAX_RINGS`].
const FIRST_RINGS: u32 = 1;
/// See [`FIRST_RINGS`].
const MAX_RINGS: u32 = 4;

/// The stencils of the conversion `conv` of the cage `coarse` (refined into
/// `fine`, its faces coming from the coarse faces `coarse_face`), found by
/// probing `linear` (see the module doc), with the shading construction's
/// `decisions`.
#[allow(clippy::too_many_arguments)]
pub fn probe(
    coarse: &Cage,
    coarse_topo: &Topology,
    fine: &Cage,
    fine_topo: &Topology,
    coarse_face: &[usize],
    conv: &Conversion,
    decisions: &tangent::Decisions,
    linear: &Linear,
    path: &Path,
) -> Result<CageStencils, SceneError> {
    let outputs = Outputs::new(fine, fine_topo, conv);
    let rest = outputs.values(conv);
    let mut rings = FIRST_RINGS;
    let combos = loop {
        match probe_with(
            coarse,
            coarse_topo,
            fine_topo,
            coarse_face,
            conv,
            &outputs,
            &rest,
            rings,
            linear,
            path,
        )? {
            Some(c) => break c,
            None if rings < MAX_RINGS => rings += 1,
            None => {
                return Err(SceneError::invalid(
                    path,
                    format!(
                        "internal: the conversion of this cage is not linear in its vertices \
                         (checked up to {MAX_RINGS} face rings): it cannot be animated by stencils"
                    ),
                ))
            }
        }
    };
    // One row per distinct combination: a point the conversion computed
    // once and copied is one row.
    let mut stencils = CageStencils {
        vertices: coarse.positions.len(),
        ..Default::default()
    };
    let mut row_of: HashMap<Vec<(u32, u32)>, u32> = HashMap::new();
    let mut rows = Vec::with_capacity(combos.len());
    for (id, terms) in combos.iter().enumerate() {
        let key: Vec<(u32, u32)> = terms.iter().map(|&(i, w)| (i, w.to_bits())).collect();
        let row = match row_of.get(&key) {
            Some(&r) => r,
            None => {
                let (reference, rest) = reference_form(terms, 1.0).ok_or_else(|| {
                    SceneError::invalid(
                        path,
                        format!("internal: control point {id} of the conversion is not an affine combination of cage vertices"),
                    )
                })?;
                let r = stencils.points.push(reference, &rest);
                row_of.insert(key, r);
                r
            }
        };
        rows.push(row);
    }
    stencils.patch_rows = (0..conv.patches.len())
        .map(|p| std::array::from_fn(|s| rows[16 * p + s]))
        .collect();
    let recipe = tangent::recipe(
        fine,
        fine_topo,
        conv,
        decisions,
        &|v| rows[outputs.corner_id[&v] as usize],
        &|a, b| rows[outputs.edge_id[&(a, b)] as usize],
        &|p, s| rows[16 * p + s],
    );
    for (p, vectors) in recipe.iter().enumerate() {
        for (k, c) in vectors.iter().enumerate() {
            let terms: Vec<(u32, f32)> = c.0.iter().map(|&(i, w)| (i, w as f32)).collect();
            let (reference, rest) = reference_form(&terms, 0.0)
                .or_else(|| zero_vector(c))
                .ok_or_else(|| {
                    SceneError::invalid(
                        path,
                        format!("internal: shading vector {k} of patch {p} is not a difference of control points"),
                    )
                })?;
            stencils.shading.push(reference, &rest);
        }
    }
    Ok(stencils)
}

/// The zero vector as a row (a tangent that cancels, e.g. of a collapsed
/// edge): relative to input 0 with no terms.
fn zero_vector(c: &Comb) -> Option<(u32, Vec<(u32, f32)>)> {
    c.0.is_empty().then(|| (0, Vec::new()))
}

/// `terms` (sorted by input) as (reference, the other terms), the reference
/// the term of the largest weight, where the weights sum to `sum` (1 for a
/// point, 0 for a vector) within rounding.
pub(super) fn reference_form(terms: &[(u32, f32)], sum: f64) -> Option<(u32, Vec<(u32, f32)>)> {
    let total: f64 = terms.iter().map(|t| f64::from(t.1)).sum();
    let size: f64 = terms.iter().map(|t| f64::from(t.1).abs()).sum();
    if terms.is_empty() || (total - sum).abs() > 1e-5 * size.max(1.0) {
        return None;
    }
    let mut best = 0;
    for (k, t) in terms.iter().enumerate() {
        if t.1.abs() > terms[best].1.abs() {
            best = k;
        }
    }
    let reference = terms[best].0;
    let rest = terms
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != best)
        .map(|(_, &t)| t)
        .collect();
    Some((reference, rest))
}

/// The terms (input, weight) of one combination, sorted by input.
type Terms = Vec<(u32, f32)>;

/// One probing pass assuming outputs reach `rings` face rings: the
/// combination of every output, or `None` where that was not enough.
#[allow(clippy::too_many_arguments)]
fn probe_with(
    coarse: &Cage,
    coarse_topo: &Topology,
    fine_topo: &Topology,
    coarse_face: &[usize],
    conv: &Conversion,
    outputs: &Outputs,
    rest: &[Vec3],
    rings: u32,
    linear: &Linear,
    path: &Path,
) -> Result<Option<Vec<Terms>>, SceneError> {
    let reach = reach(coarse, coarse_topo, rings);
    let (set_of, sets) = candidate_sets(&reach, fine_topo, coarse_face, conv, outputs);
    let (colours, count) = colour(coarse.positions.len(), &sets);
    log::debug!(
        "stencils: {} vertices, {} outputs, {} candidate sets, {rings} rings: {count} colours, {} runs",
        coarse.positions.len(),
        outputs.len(),
        sets.len(),
        count.div_ceil(3)
    );
    // Per set, its vertices by colour.
    let by_colour: Vec<Vec<(u32, u32)>> = sets
        .iter()
        .map(|s| {
            let mut v: Vec<(u32, u32)> = s.iter().map(|&v| (colours[v as usize], v)).collect();
            v.sort_unstable();
            v
        })
        .collect();
    let results = run_probes(coarse, &colours, count.div_ceil(3), linear);
    let mut combos: Vec<Vec<(u32, f32)>> = vec![Vec::new(); outputs.len()];
    for (run, out) in results.into_iter().enumerate() {
        let out = out?;
        if out.patches.len() != conv.patches.len() {
            return Err(SceneError::invalid(
                path,
                "internal: the conversion made a different number of patches for another pose",
            ));
        }
        let values = outputs.values(&out);
        for (id, value) in values.iter().enumerate() {
            for ch in 0..3 {
                let w = value[ch];
                if w == 0.0 {
                    continue;
                }
                let c = 3 * run as u32 + ch as u32;
                let set = &by_colour[set_of[id] as usize];
                let Ok(k) = set.binary_search_by_key(&c, |t| t.0) else {
                    return Ok(None);
                };
                combos[id].push((set[k].1, w));
            }
        }
    }
    for c in &mut combos {
        c.sort_unstable_by_key(|t| t.0);
    }
    Ok(gives_rest(coarse, &combos, rest).then_some(combos))
}

/// The candidate set of each output (an index into the sets) and the
/// distinct sets: the vertices within the reach of the output's coarse
/// faces, sorted.
fn candidate_sets(
    reach: &[Vec<u32>],
    fine_topo: &Topology,
    coarse_face: &[usize],
    conv: &Conversion,
    outputs: &Outputs,
) -> (Vec<u32>, Vec<Vec<u32>>) {
    let mut set_of: Vec<u32> = Vec::with_capacity(outputs.len());
    let mut sets: Vec<Vec<u32>> = Vec::new();
    let mut set_id: HashMap<Vec<usize>, u32> = HashMap::new();
    for id in 0..outputs.len() {
        let mut faces: Vec<usize> = outputs
            .faces(id, fine_topo, conv)
            .into_iter()
            .map(|f| coarse_face[f])
            .collect();
        faces.sort_unstable();
        faces.dedup();
        let s = *set_id.entry(faces.clone()).or_insert_with(|| {
            let mut vs: Vec<u32> = faces
                .iter()
                .flat_map(|&f| reach[f].iter().copied())
                .collect();
            vs.sort_unstable();
            vs.dedup();
            sets.push(vs);
            sets.len() as u32 - 1
        });
        set_of.push(s);
    }
    (set_of, sets)
}

/// Converts one probe cage per run (run r: the vertices of colours 3r,
/// 3r + 1, 3r + 2 at the unit x, y, z, every other vertex at 0), the results
/// in run order.
fn run_probes(
    coarse: &Cage,
    colours: &[u32],
    runs: u32,
    linear: &Linear,
) -> Vec<Result<Conversion, SceneError>> {
    let probe_cage = |run: u32| {
        let mut cage = coarse.clone();
        for (v, p) in cage.positions.iter_mut().enumerate() {
            let c = colours[v];
            *p = DVec3::ZERO;
            if c != u32::MAX && c / 3 == run {
                p[(c % 3) as usize] = 1.0;
            }
        }
        cage
    };
    // The runs are independent: on as many threads as the machine has.
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(runs as usize)
        .max(1);
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let probe_cage = &probe_cage;
                scope.spawn(move || {
                    (0..runs)
                        .filter(|r| *r as usize % threads == t)
                        .map(|r| (r, linear(&probe_cage(r))))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        let mut all: Vec<(u32, Result<Conversion, SceneError>)> = workers
            .into_iter()
            .flat_map(|w| w.join().expect("a probing thread panicked"))
            .collect();
        all.sort_by_key(|r| r.0);
        all.into_iter().map(|r| r.1).collect()
    })
}

/// Whether the combinations give the conversion of the cage as loaded
/// (`rest`), within rounding.
fn gives_rest(coarse: &Cage, combos: &[Terms], rest: &[Vec3]) -> bool {
    let x: Vec<DVec3> = coarse.positions.clone();
    let scale = x
        .iter()
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()))
        .max(f64::MIN_POSITIVE);
    for (id, terms) in combos.iter().enumerate() {
        let got: DVec3 = terms
            .iter()
            .fold(DVec3::ZERO, |s, &(i, w)| s + x[i as usize] * f64::from(w));
        if (got - rest[id].as_dvec3()).abs().max_element() > 1e-5 * scale {
            return false;
        }
    }
    true
}
