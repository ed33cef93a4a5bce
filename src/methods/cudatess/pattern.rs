//! The tessellation pattern of one patch (Schwarz and Stamminger, Fig. 3):
//! the CPU twin of `ct_pattern`, `ct_grid_vertex` and the index pass in
//! `glsl/common/cudatess.glsl` and `glsl/cudatess/indices.comp`, for the tests
//! (counts, the triangles themselves) and for reading the GPU's vertex
//! buffer back (which vertex is which).

/// A patch's pattern from its four edge factors (0: u = 0, 1: v = 0,
/// 2: u = 1, 3: v = 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pattern {
    /// Edge factors.
    pub e: [u32; 4],
    /// Core factor along u: the smaller of the two u edges'.
    pub m: u32,
    /// Core factor along v.
    pub n: u32,
    /// A transition strip along edge k.
    pub strip: [bool; 4],
    /// Local index of edge k's first interior vertex.
    pub edge_base: [u32; 4],
    /// Local index of grid vertex (1, 1).
    pub interior_base: u32,
    /// Vertices.
    pub vertices: u32,
    /// Indices.
    pub indices: u32,
    /// Core cells: i in core[0]..core[1], j in core[2]..core[3].
    pub core: [u32; 4],
}

/// Where a local vertex lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    /// Corner k: (0,0), (1,0), (1,1), (0,1).
    Corner(u32),
    /// Vertex s (1..e[k]) of edge k.
    Edge(u32, u32),
    /// Interior grid vertex (i, j).
    Interior(u32, u32),
}

const STARTS: [u32; 4] = [0, 0, 1, 3];
const ENDS: [u32; 4] = [3, 1, 2, 2];

impl Pattern {
    /// The pattern for edge factors `e` (each at least 1).
    pub fn new(e: [u32; 4]) -> Self {
        let m = e[1].min(e[3]);
        let n = e[0].min(e[2]);
        let strip = [e[0] > n, e[1] > m, e[2] > n, e[3] > m];
        let mut edge_base = [4u32; 4];
        for k in 1..4 {
            edge_base[k] = edge_base[k - 1] + (e[k - 1] - 1);
        }
        let interior_base = edge_base[3] + (e[3] - 1);
        let vertices = interior_base + (m - 1) * (n - 1);
        let core = [
            u32::from(strip[0]),
            if strip[2] { m - 1 } else { m },
            u32::from(strip[1]),
            if strip[3] { n - 1 } else { n },
        ];
        let (cols, rows) = (core[1] - core[0], core[3] - core[2]);
        let mut tris = 2 * cols * rows;
        for k in 0..4 {
            if strip[k] {
                tris += e[k] + if k % 2 == 0 { rows } else { cols };
            }
        }
        Pattern {
            e,
            m,
            n,
            strip,
            edge_base,
            interior_base,
            vertices,
            indices: 3 * tris,
            core,
        }
    }

    /// Local index of vertex `s` (0..=e[k]) along edge `k`.
    pub fn edge_vertex(&self, k: usize, s: u32) -> u32 {
        if s == 0 {
            STARTS[k]
        } else if s == self.e[k] {
            ENDS[k]
        } else {
            self.edge_base[k] + s - 1
        }
    }

    /// Local index of grid point (i, j) of the core or a strip's inner side.
    pub fn grid_vertex(&self, i: u32, j: u32) -> u32 {
        if j == 0 {
            self.edge_vertex(1, i)
        } else if j == self.n {
            self.edge_vertex(3, i)
        } else if i == 0 {
            self.edge_vertex(0, j)
        } else if i == self.m {
            self.edge_vertex(2, j)
        } else {
            self.interior_base + (j - 1) * (self.m - 1) + (i - 1)
        }
    }

    /// Where local vertex `k` lies.
    pub fn place(&self, k: u32) -> Place {
        if k < 4 {
            return Place::Corner(k);
        }
        if k >= self.interior_base {
            let cols = self.m - 1;
            let x = k - self.interior_base;
            return Place::Interior(x % cols + 1, x / cols + 1);
        }
        let mut s = k - 4;
        let mut edge = 0;
        while s >= self.e[edge] - 1 {
            s -= self.e[edge] - 1;
            edge += 1;
        }
        Place::Edge(edge as u32, s + 1)
    }

    /// Inner-side vertex `l` of the strip along edge `k`.
    fn inner_vertex(&self, k: usize, l: u32) -> u32 {
        let c = self.core;
        match k {
            0 => self.grid_vertex(c[0], c[2] + l),
            1 => self.grid_vertex(c[0] + l, c[2]),
            2 => self.grid_vertex(c[1], c[2] + l),
            _ => self.grid_vertex(c[0] + l, c[3]),
        }
    }

    /// The triangles, local indices, in the index pass's order.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        let mut out = Vec::with_capacity(self.indices as usize / 3);
        let c = self.core;
        for j in c[2]..c[3] {
            for i in c[0]..c[1] {
                let v00 = self.grid_vertex(i, j);
                let v10 = self.grid_vertex(i + 1, j);
                let v11 = self.grid_vertex(i + 1, j + 1);
                let v01 = self.grid_vertex(i, j + 1);
                out.push([v00, v10, v11]);
                out.push([v00, v11, v01]);
            }
        }
        for k in 0..4 {
            if !self.strip[k] {
                continue;
            }
            let a = self.e[k];
            let b = if k % 2 == 0 { c[3] - c[2] } else { c[1] - c[0] };
            let mirror = k == 0 || k == 3;
            let (mut i, mut l) = (0u32, 0u32);
            let mut q = a as i64 - b as i64;
            while i < a || l < b {
                let edge_step = l == b || (i < a && q >= 0);
                let o = self.edge_vertex(k, i);
                let (x, y) = if edge_step {
                    let xy = (self.edge_vertex(k, i + 1), self.inner_vertex(k, l));
                    i += 1;
                    q -= 2 * b as i64;
                    xy
                } else {
                    let xy = (self.inner_vertex(k, l + 1), self.inner_vertex(k, l));
                    l += 1;
                    q += 2 * a as i64;
                    xy
                };
                out.push(if mirror { [o, y, x] } else { [o, x, y] });
            }
        }
        out
    }

    /// The (u, v) of local vertex `k` in exact rationals, as f64 (the GPU
    /// rounds these to f32; edges use the symmetric parameter).
    pub fn uv(&self, k: u32) -> (f64, f64) {
        match self.place(k) {
            Place::Corner(c) => [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][c as usize],
            Place::Edge(e, s) => {
                let t = f64::from(s) / f64::from(self.e[e as usize]);
                [(0.0, t), (t, 0.0), (1.0, t), (t, 1.0)][e as usize]
            }
            Place::Interior(i, j) => (
                f64::from(i) / f64::from(self.m),
                f64::from(j) / f64::from(self.n),
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area of a triangle in (u, v).
    fn area2(p: &Pattern, t: [u32; 3]) -> f64 {
        let [a, b, c] = t.map(|k| p.uv(k));
        (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
    }

    /// Every factor combination the pattern can meet (both u edges at least
    /// the core's and so on, as the max over patches makes them) up to 7:
    /// the counts match, every vertex is used, every triangle is
    /// counter-clockwise with positive area, the areas sum to the unit
    /// square, and every interior edge of the mesh has exactly two
    /// triangles on opposite sides while boundary edges (the patch edges'
    /// segments, e[k] of them) have one: a watertight fan of the domain.
    #[test]
    fn patterns_tile_the_square_without_t_junctions() {
        for e0 in 1..=7u32 {
            for e1 in 1..=7 {
                for e2 in 1..=7 {
                    for e3 in 1..=7 {
                        check([e0, e1, e2, e3]);
                    }
                }
            }
        }
        check([1, 64, 1, 64]);
        check([64, 1, 37, 2]);
        check([64, 64, 64, 64]);
    }

    fn check(e: [u32; 4]) {
        let p = Pattern::new(e);
        let tris = p.triangles();
        assert_eq!(tris.len() as u32 * 3, p.indices, "{e:?}");
        let mut used = vec![false; p.vertices as usize];
        let mut sum = 0.0;
        let mut edges: std::collections::HashMap<(u32, u32), i32> = Default::default();
        for &t in &tris {
            let a = area2(&p, t);
            assert!(
                a > 1e-12,
                "{e:?}: triangle {t:?} is not counter-clockwise ({a})"
            );
            sum += a / 2.0;
            for k in 0..3 {
                used[t[k] as usize] = true;
                let (x, y) = (t[k], t[(k + 1) % 3]);
                // +1 for x→y, -1 for y→x: a shared edge cancels.
                *edges.entry((x.min(y), x.max(y))).or_default() += if x < y { 1 } else { -1 };
            }
        }
        assert!((sum - 1.0).abs() < 1e-9, "{e:?}: area {sum}");
        assert!(used.iter().all(|&u| u), "{e:?}: an unused vertex");
        let boundary: u32 = e.iter().sum();
        let open = edges.values().filter(|&&c| c != 0).count() as u32;
        assert_eq!(
            open, boundary,
            "{e:?}: {open} unmatched edges, {boundary} boundary segments"
        );
        for (&(x, y), &c) in &edges {
            assert!(c.abs() <= 1, "{e:?}: edge {x}-{y} used {c} times one way");
        }
        // Boundary segments are exactly the edges' own.
        for k in 0..4 {
            for s in 0..e[k] {
                let (x, y) = (p.edge_vertex(k, s), p.edge_vertex(k, s + 1));
                assert_ne!(
                    edges[&(x.min(y), x.max(y))],
                    0,
                    "{e:?}: edge {k} segment {s}"
                );
            }
        }
    }

    #[test]
    fn places_round_trip() {
        let p = Pattern::new([3, 5, 4, 2]);
        assert_eq!(p.place(0), Place::Corner(0));
        assert_eq!(p.place(4), Place::Edge(0, 1));
        assert_eq!(p.place(p.edge_base[2]), Place::Edge(2, 1));
        assert_eq!(p.place(p.interior_base), Place::Interior(1, 1));
        for k in 0..p.vertices {
            match p.place(k) {
                Place::Interior(i, j) => assert_eq!(p.grid_vertex(i, j), k),
                Place::Edge(e, s) => assert_eq!(p.edge_vertex(e as usize, s), k),
                Place::Corner(_) => {}
            }
        }
    }
}
