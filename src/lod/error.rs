//! How far a level lies from the limit surface, measured: the largest
//! distance from points sampled on one surface to the other, both ways
//! (a one-sided measure misses a level that bulges out where the surface
//! does not, or a surface feature the level cut off).

use glam::Vec3;

use super::mesh::TriMesh;
use crate::patch::bezier::BezierPatch;

/// The closest point to `p` on triangle `t` (by regions of the triangle's
/// plane: a corner, an edge or the face).
pub fn closest_on_triangle(p: Vec3, t: [Vec3; 3]) -> Vec3 {
    let [a, b, c] = t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// The barycentric weights of `p` (a point of triangle `t`'s plane) in `t`;
/// a degenerate triangle's first corner takes all.
pub fn barycentric(p: Vec3, t: [Vec3; 3]) -> Vec3 {
    let [a, b, c] = t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (ab.dot(ab), ab.dot(ac), ac.dot(ac));
    let (d20, d21) = (ap.dot(ab), ap.dot(ac));
    let denom = d00 * d11 - d01 * d01;
    if denom.abs() <= f32::EPSILON * d00 * d11 {
        return Vec3::X;
    }
    let v = (d11 * d20 - d01 * d21) / denom;
    let w = (d00 * d21 - d01 * d20) / denom;
    Vec3::new(1.0 - v - w, v, w)
}

/// Most cells of a [`NearestTriangle`] grid (the cell grows to keep
/// within it).
const MAX_CELLS: f32 = 2.0e6;

/// A triangle mesh bucketed on a uniform grid for nearest-point queries:
/// per cell the triangles whose box touches it, stored as one list with
/// each cell's start (compressed rows).
pub struct NearestTriangle<'a> {
    mesh: &'a TriMesh,
    lo: Vec3,
    cell: f32,
    dims: [i64; 3],
    starts: Vec<u32>,
    items: Vec<u32>,
}

impl<'a> NearestTriangle<'a> {
    /// Buckets every triangle in the cells its box touches; the cell is
    /// about the mean edge, so a cell holds a few.
    pub fn new(mesh: &'a TriMesh) -> Self {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in &mesh.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let extent = (hi - lo).max(Vec3::splat(1e-12));
        let mut edge_sum = 0.0f64;
        for t in 0..mesh.triangles() {
            let [a, b, c] = mesh.triangle(t);
            edge_sum += f64::from((b - a).length() + (c - b).length() + (a - c).length());
        }
        let mean_edge = (edge_sum / (3 * mesh.triangles().max(1)) as f64) as f32;
        let fit = (extent.x * extent.y * extent.z / MAX_CELLS).cbrt();
        let cell = mean_edge
            .max(extent.max_element() / 256.0)
            .max(fit)
            .max(1e-12);
        let dims = (extent / cell)
            .ceil()
            .as_i64vec3()
            .max(glam::I64Vec3::ONE)
            .to_array();
        let mut grid = Self {
            mesh,
            lo,
            cell,
            dims,
            starts: Vec::new(),
            items: Vec::new(),
        };
        let cells = (dims[0] * dims[1] * dims[2]) as usize;
        // Twice over the triangles: count per cell, then place.
        let mut counts = vec![0u32; cells + 1];
        grid.each_cell_of_each_triangle(|c, _| counts[c] += 1);
        let mut total = 0u32;
        for n in counts.iter_mut() {
            let here = *n;
            *n = total;
            total += here;
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; total as usize];
        grid.each_cell_of_each_triangle(|c, t| {
            items[fill[c] as usize] = t;
            fill[c] += 1;
        });
        grid.starts = counts;
        grid.items = items;
        grid
    }

    fn each_cell_of_each_triangle(&self, mut visit: impl FnMut(usize, u32)) {
        for t in 0..self.mesh.triangles() {
            let [a, b, c] = self.mesh.triangle(t);
            let (l, h) = (self.cell_of(a.min(b).min(c)), self.cell_of(a.max(b).max(c)));
            for x in l[0]..=h[0] {
                for y in l[1]..=h[1] {
                    for z in l[2]..=h[2] {
                        if let Some(k) = self.index([x, y, z]) {
                            visit(k, t as u32);
                        }
                    }
                }
            }
        }
    }

    fn cell_of(&self, p: Vec3) -> [i64; 3] {
        let c = ((p - self.lo) / self.cell).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    }

    /// The index of cell `c`, if it is in the grid.
    fn index(&self, c: [i64; 3]) -> Option<usize> {
        let [dx, dy, dz] = self.dims;
        let inside = (0..dx).contains(&c[0]) && (0..dy).contains(&c[1]) && (0..dz).contains(&c[2]);
        inside.then(|| ((c[2] * dy + c[1]) * dx + c[0]) as usize)
    }

    /// The distance from `p` to the mesh: shells of cells around `p`'s
    /// cell, outwards, until the nearest triangle found lies nearer than
    /// any cell not yet searched.
    pub fn distance(&self, p: Vec3) -> f32 {
        self.nearest(p).0
    }

    /// The distance from `p` to the mesh and the triangle that nearest
    /// point lies on (see [`NearestTriangle::distance`]).
    pub fn nearest(&self, p: Vec3) -> (f32, usize) {
        let c = self.cell_of(p);
        // How far p lies inside its own cell: every cell beyond shell r is
        // at least r cells and this much away.
        let own = self.lo + Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) * self.cell;
        let inner = (p - own)
            .min(own + Vec3::splat(self.cell) - p)
            .min_element()
            .max(0.0);
        let mut best = (f32::MAX, 0);
        // Past this shell every cell of the grid has been searched.
        let reach = (0..3)
            .map(|i| c[i].abs().max((self.dims[i] - 1 - c[i]).abs()))
            .max()
            .unwrap_or(0)
            + 1;
        for r in 0..=reach {
            for x in c[0] - r..=c[0] + r {
                for y in c[1] - r..=c[1] + r {
                    for z in c[2] - r..=c[2] + r {
                        let shell =
                            (x - c[0]).abs() == r || (y - c[1]).abs() == r || (z - c[2]).abs() == r;
                        let Some(k) = self.index([x, y, z]).filter(|_| shell) else {
                            continue;
                        };
                        for &t in &self.items[self.starts[k] as usize..self.starts[k + 1] as usize]
                        {
                            let q = closest_on_triangle(p, self.mesh.triangle(t as usize));
                            let d = q.distance(p);
                            if d < best.0 {
                                best = (d, t as usize);
                            }
                        }
                    }
                }
            }
            if best.0 <= r as f32 * self.cell + inner {
                break;
            }
        }
        best
    }
}

/// An upper bound of how far the welded grid mesh of `patches` at `n`
/// cells a side ([`super::mesh::limit_mesh`]) lies from the surface,
/// sampled: each cell's centre and the midpoints of its sides and diagonal,
/// measured to the cell's own two triangles (the mesh is no farther than
/// those).
pub fn grid_error(patches: &[BezierPatch], n: usize) -> f32 {
    let h = 1.0 / n as f32;
    let mut worst = 0.0f32;
    for p in patches {
        for j in 0..n {
            for i in 0..n {
                let (u0, v0) = (i as f32 * h, j as f32 * h);
                let (u1, v1) = (u0 + h, v0 + h);
                let [a, b, c, d] = [
                    p.eval(u0, v0),
                    p.eval(u1, v0),
                    p.eval(u1, v1),
                    p.eval(u0, v1),
                ];
                let halves = [
                    (u0 + 0.5 * h, v0),
                    (u0, v0 + 0.5 * h),
                    (u0 + 0.5 * h, v0 + 0.5 * h),
                ];
                let quarter = [
                    (u0 + 0.75 * h, v0 + 0.25 * h),
                    (u0 + 0.25 * h, v0 + 0.75 * h),
                ];
                for (u, v) in halves.into_iter().chain(quarter) {
                    let s = p.eval(u, v);
                    let near = closest_on_triangle(s, [a, b, c])
                        .distance(s)
                        .min(closest_on_triangle(s, [a, c, d]).distance(s));
                    worst = worst.max(near);
                }
            }
        }
    }
    worst
}

/// Points of the limit surface: each patch at `n` + 1 by `n` + 1
/// parameters, its corners included.
pub fn surface_samples(patches: &[BezierPatch], n: usize) -> Vec<Vec3> {
    let mut out = Vec::with_capacity(patches.len() * (n + 1) * (n + 1));
    for p in patches {
        for j in 0..=n {
            for i in 0..=n {
                out.push(p.eval(i as f32 / n as f32, j as f32 / n as f32));
            }
        }
    }
    out
}

/// Points of a mesh: every vertex, every edge's midpoint and every
/// triangle's centroid.
pub fn mesh_samples(mesh: &TriMesh) -> Vec<Vec3> {
    let mut out = mesh.positions.clone();
    for t in 0..mesh.triangles() {
        let [a, b, c] = mesh.triangle(t);
        out.extend([
            (a + b) * 0.5,
            (b + c) * 0.5,
            (c + a) * 0.5,
            (a + b + c) / 3.0,
        ]);
    }
    out
}

/// Samples a worker takes at a time in [`fold_chunks`].
const CHUNK: usize = 4096;

/// `fold` over `items` in chunks of [`CHUNK`], the chunks split among the
/// machine's cores, their results merged in chunk order: the same result
/// (sums included) whatever the number of cores, so a level's normals and
/// errors do not depend on the machine that made them.
pub(super) fn fold_chunks<T: Sync, A: Send>(
    items: &[T],
    fold: impl Fn(&[T]) -> A + Sync,
    merge: impl Fn(A, A) -> A,
    empty: A,
) -> A {
    let chunks: Vec<&[T]> = items.chunks(CHUNK).collect();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let per = chunks.len().div_ceil(threads).max(1);
    let results: Vec<A> = std::thread::scope(|s| {
        let fold = &fold;
        let workers: Vec<_> = chunks
            .chunks(per)
            .map(|mine| s.spawn(move || mine.iter().map(|c| fold(c)).collect::<Vec<A>>()))
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("a level worker does not panic"))
            .collect()
    });
    results.into_iter().fold(empty, merge)
}

/// The largest distance from any of `points` to `mesh`.
pub fn max_distance(points: &[Vec3], mesh: &TriMesh) -> f32 {
    let near = NearestTriangle::new(mesh);
    fold_chunks(
        points,
        |part| part.iter().map(|p| near.distance(*p)).fold(0.0, f32::max),
        f32::max,
        0.0,
    )
}

/// A point of the limit surface, its unit normal and the surface area it
/// stands for.
#[derive(Clone, Copy, Debug)]
pub struct NormalSample {
    /// The point.
    pub point: Vec3,
    /// The unit normal there (∂u × ∂v).
    pub normal: Vec3,
    /// Its share of the surface's area (trapezoid weights of the
    /// parameter grid times |∂u × ∂v|).
    pub area: f32,
}

/// Points of the limit surface with their normals and areas: each patch
/// at `n` + 1 by `n` + 1 parameters, as [`surface_samples`]; a point whose
/// normal is undefined (a collapsed corner) is left out.
pub fn surface_normals(patches: &[BezierPatch], n: usize) -> Vec<NormalSample> {
    let mut out = Vec::with_capacity(patches.len() * (n + 1) * (n + 1));
    let cell = 1.0 / (n * n) as f32;
    let edge = |i: usize| if i == 0 || i == n { 0.5 } else { 1.0 };
    for p in patches {
        for j in 0..=n {
            for i in 0..=n {
                let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                let (du, dv) = p.partials(u, v);
                let normal = p.normal(u, v).normalize_or_zero();
                if normal != Vec3::ZERO {
                    out.push(NormalSample {
                        point: p.eval(u, v),
                        normal,
                        area: du.cross(dv).length() * cell * edge(i) * edge(j),
                    });
                }
            }
        }
    }
    out
}

/// The cosine of the largest angle between a surface sample's normal and
/// a level triangle's for the sample to count in the triangle's vertex
/// normals (60°: a rounded edge a coarse triangle spans counts, a sharp
/// crease of 90° does not).
const FIT_COS: f32 = 0.5;

/// Sets each vertex normal of `mesh` to the one that stands best for the
/// surface its triangles stand in for: the area-weighted mean of the
/// normals of the surface `samples` whose nearest point lies on a triangle
/// of the vertex, each weighted by the vertex's barycentric share of that
/// point. A sample whose normal lies more than 60° from that triangle's
/// (across a crease the triangle only touches, or the far side of a thin
/// sheet) is left out, and so, at a vertex on a crease (more than one
/// normal: [`TriMesh::split`]), is one not nearer the vertex's own normal
/// than another side's; a vertex no sample reaches keeps its normal. The limit surface's normal at a vertex is not that: where a
/// coarse triangle spans a rounded edge and a flat face, the edge's normal
/// at its corner tilts the whole face.
pub fn fit_normals(mesh: &mut TriMesh, samples: &[NormalSample]) {
    let sums = {
        let mesh = &*mesh;
        let near = NearestTriangle::new(mesh);
        let vertices = mesh.positions.len();
        fold_chunks(
            samples,
            |part| {
                let mut sums = vec![Vec3::ZERO; vertices];
                for s in part {
                    add_fitted(mesh, &near, s, &mut sums);
                }
                sums
            },
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
                a
            },
            vec![Vec3::ZERO; vertices],
        )
    };
    for (normals, sum) in mesh.normals.iter_mut().zip(sums) {
        if let (Some(n), Some(fitted)) = (normals.first_mut(), sum.try_normalize()) {
            *n = fitted;
        }
    }
}

/// Adds sample `s`'s weighted normal to the sums of the vertices of its
/// nearest triangle that take it ([`fit_normals`]).
fn add_fitted(mesh: &TriMesh, near: &NearestTriangle<'_>, s: &NormalSample, sums: &mut [Vec3]) {
    let (_, t) = near.nearest(s.point);
    let corners = mesh.triangle(t);
    let [a, b, c] = corners;
    if (b - a).cross(c - a).normalize_or_zero().dot(s.normal) < FIT_COS {
        return;
    }
    let w = barycentric(closest_on_triangle(s.point, corners), corners).max(Vec3::ZERO);
    for k in 0..3 {
        let v = mesh.indices[3 * t + k] as usize;
        // At a crease vertex, only samples nearer its own side's normal
        // than any other's: one across the crease (on the crease itself,
        // this side's triangle may be nearest), or of a third face a
        // collapse folded onto this corner.
        let list = &mesh.normals[v];
        let own = list.first().map_or(1.0, |m| m.dot(s.normal));
        if list.iter().skip(1).any(|m| m.dot(s.normal) >= own) {
            continue;
        }
        sums[v] += s.normal * (s.area * w[k]);
    }
}

/// The unit normal `mesh` is shaded with at its point nearest `p`: its
/// vertex normals interpolated, as the rasterizer does.
pub fn shaded_normal(mesh: &TriMesh, near: &NearestTriangle<'_>, p: Vec3) -> Vec3 {
    let (_, t) = near.nearest(p);
    let corners = mesh.triangle(t);
    let w = barycentric(closest_on_triangle(p, corners), corners);
    let ids = &mesh.indices[3 * t..3 * t + 3];
    (0..3)
        .map(|k| mesh.normals[ids[k] as usize][0] * w[k])
        .sum::<Vec3>()
        .normalize_or_zero()
}

/// The surface-area-weighted mean angle, in radians, between the limit
/// surface's normal at `samples` and the normal `mesh` is shaded with at
/// its nearest point (its vertex normals interpolated, as the rasterizer
/// does); `two_sided`: a normal and its opposite are one (such a model is
/// lit from the side it is seen from).
pub fn normal_error(samples: &[NormalSample], mesh: &TriMesh, two_sided: bool) -> f32 {
    let near = NearestTriangle::new(mesh);
    let angle = |s: &NormalSample| {
        let cos = shaded_normal(mesh, &near, s.point).dot(s.normal);
        let cos = if two_sided { cos.abs() } else { cos };
        f64::from(cos.clamp(-1.0, 1.0).acos())
    };
    let (sum, area) = fold_chunks(
        samples,
        |part| {
            part.iter().fold((0.0f64, 0.0f64), |(sum, area), s| {
                let a = f64::from(s.area);
                (sum + angle(s) * a, area + a)
            })
        },
        |x, y| (x.0 + y.0, x.1 + y.1),
        (0.0, 0.0),
    );
    (sum / area.max(f64::MIN_POSITIVE)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closest_point_is_in_every_region_of_the_triangle() {
        let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let cases = [
            (Vec3::new(0.2, 0.2, 1.0), Vec3::new(0.2, 0.2, 0.0)),
            (Vec3::new(-1.0, -1.0, 0.0), Vec3::ZERO),
            (Vec3::new(2.0, -0.5, 0.0), Vec3::X),
            (Vec3::new(0.5, -1.0, 3.0), Vec3::new(0.5, 0.0, 0.0)),
            (Vec3::new(-1.0, 0.5, 0.0), Vec3::new(0.0, 0.5, 0.0)),
            (Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.5, 0.5, 0.0)),
        ];
        for (p, want) in cases {
            assert!(closest_on_triangle(p, t).distance(want) < 1e-6, "{p}");
        }
    }

    #[test]
    fn a_finer_mesh_of_the_ball_is_shaded_nearer_its_normals() {
        let ball = super::super::mesh::shapes::ball(2);
        let samples = surface_normals(&ball, 8);
        let error = |cells: usize| {
            let mesh = super::super::mesh::limit_mesh(&ball, cells, &super::super::mesh::plain_uv);
            normal_error(&samples, &mesh, false).to_degrees()
        };
        let (fine, coarse) = (error(8), error(1));
        // The ball's patches meet at an angle across the cube's edges
        // (their welded normals are averaged there): not zero even fine.
        assert!(fine < 3.0, "{fine}");
        assert!(coarse > 2.0 * fine, "{coarse} against {fine}");
        // Turned inside out, one-sided: every normal opposite.
        let mut flipped = super::super::mesh::limit_mesh(&ball, 8, &super::super::mesh::plain_uv);
        flipped.normals.iter_mut().flatten().for_each(|n| *n = -*n);
        let inside_out = normal_error(&samples, &flipped, false).to_degrees();
        assert!(inside_out > 170.0, "{inside_out}");
        let two_sided = normal_error(&samples, &flipped, true).to_degrees();
        assert!(
            (two_sided - fine).abs() < 1e-3,
            "{two_sided} against {fine}"
        );
    }

    #[test]
    fn chunks_merge_in_order_whatever_the_cores() {
        // Float sums whose value depends on the order they are added in.
        let items: Vec<f32> = (0..3 * CHUNK + 17)
            .map(|k| 1.0 / (1.0 + k as f32 * 0.37))
            .collect();
        let in_order = items
            .chunks(CHUNK)
            .map(|c| c.iter().sum::<f32>())
            .fold(0.0f32, |a, b| a + b);
        let got = fold_chunks(&items, |c| c.iter().sum::<f32>(), |a, b| a + b, 0.0);
        assert_eq!(got.to_bits(), in_order.to_bits());
        assert_eq!(
            fold_chunks(&[] as &[f32], |_| 1.0f32, |a, b| a + b, 0.0),
            0.0
        );
    }

    #[test]
    fn the_grid_finds_what_brute_force_finds() {
        let mesh = super::super::mesh::limit_mesh(
            &super::super::mesh::shapes::ball(1),
            3,
            &super::super::mesh::plain_uv,
        );
        let near = NearestTriangle::new(&mesh);
        for k in 0..200 {
            let s = k as f32 * 0.37;
            let p = Vec3::new(s.sin(), (s * 1.3).cos(), (s * 0.7).sin()) * (0.2 + 0.01 * k as f32);
            let brute = (0..mesh.triangles())
                .map(|t| closest_on_triangle(p, mesh.triangle(t)).distance(p))
                .fold(f32::MAX, f32::min);
            assert_eq!(near.distance(p), brute, "{p}");
        }
    }
}
