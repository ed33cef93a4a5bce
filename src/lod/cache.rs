//! Levels kept on disk between runs, so a scene's levels are made once per
//! build of the program, not at every load (the herd's car takes about
//! 20 s, the kitchen's models 30 s).
//!
//! A model's levels are filed under a key of everything they are made
//! from: its patches, its texture coordinates where the welded mesh
//! samples them, whether it is two-sided, and the shading bound; and under
//! a folder of the executable that made them (its size and modification
//! time), so a rebuilt program, whose simplifier or measures may differ,
//! never reads another's levels. Storing removes the folders of all but
//! the three most recent other builds. A file that cannot be read whole is
//! made again and replaced.

use std::cell::Cell;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::mesh::TriMesh;
use super::{Level, SOURCE_GRID};
use crate::patch::bezier::BezierPatch;

/// The environment variable that names the cache's folder; set empty, no
/// cache is used.
pub const ENV: &str = "BEZIER_SUBDIV_CACHE";

/// The first bytes of a cache file (and its format's version).
const MAGIC: &[u8; 8] = b"BZLOD001";

/// Where levels are kept, and what this run found there.
pub struct LevelCache {
    /// This build's folder.
    dir: PathBuf,
    /// Models whose levels were read from it.
    pub hits: Cell<usize>,
    /// Models whose levels were made and stored.
    pub stored: Cell<usize>,
}

impl LevelCache {
    /// The cache in `$BEZIER_SUBDIV_CACHE`, else `$XDG_CACHE_HOME/bezier-subdiv`,
    /// else `$HOME/.cache/bezier-subdiv`, in a folder of this executable;
    /// `None` when the variable is set empty or no folder is known.
    pub fn from_env() -> Option<Self> {
        let root = match std::env::var_os(ENV) {
            Some(v) if v.is_empty() => return None,
            Some(v) => PathBuf::from(v),
            None => std::env::var_os("XDG_CACHE_HOME")
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
                .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".cache")))?
                .join("bezier-subdiv"),
        };
        Some(Self::at(&root.join("levels"), &build_id()?))
    }

    /// The cache under `root`, in the folder `build`.
    pub fn at(root: &Path, build: &str) -> Self {
        Self {
            dir: root.join(build),
            hits: Cell::new(0),
            stored: Cell::new(0),
        }
    }

    /// This build's folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The levels of a model from the cache, or made by `make` and stored
    /// (a cache that cannot be written is passed by: the levels are made
    /// all the same).
    pub fn levels(
        &self,
        patches: &[BezierPatch],
        st: &dyn Fn(usize, f32, f32) -> [f32; 2],
        two_sided: bool,
        most_normal_error: f32,
        make: impl FnOnce() -> Vec<Level>,
    ) -> Vec<Level> {
        let path = self.dir.join(format!(
            "{}.lod",
            key(patches, st, two_sided, most_normal_error)
        ));
        if let Some(levels) = std::fs::read(&path).ok().and_then(|b| decode(&b)) {
            self.hits.set(self.hits.get() + 1);
            return levels;
        }
        let levels = make();
        if self.store(&path, &levels).is_ok() {
            self.stored.set(self.stored.get() + 1);
        }
        levels
    }

    fn store(&self, path: &Path, levels: &[Level]) -> std::io::Result<()> {
        std::fs::create_dir_all(&self.dir)?;
        self.forget_old_builds();
        crate::files::write_atomic(path, &encode(levels))
    }

    /// Removes the folders of all but the [`OTHER_BUILDS`] most recently
    /// written other builds: a rebuilt program never reads them again,
    /// but the test binaries and the program of one build each have their
    /// own, and should not remove each other's.
    fn forget_old_builds(&self) {
        let (Some(parent), Some(own)) = (self.dir.parent(), self.dir.file_name()) else {
            return;
        };
        let Ok(entries) = std::fs::read_dir(parent) else {
            return;
        };
        let mut others: Vec<(std::time::SystemTime, PathBuf)> = entries
            .flatten()
            .filter(|e| e.file_name() != own && e.path().is_dir())
            .filter_map(|e| Some((e.metadata().ok()?.modified().ok()?, e.path())))
            .collect();
        others.sort_by_key(|o| std::cmp::Reverse(o.0));
        for (_, old) in others.iter().skip(OTHER_BUILDS) {
            let _ = std::fs::remove_dir_all(old);
        }
    }
}

/// How many other builds' folders storing leaves (the most recent).
pub const OTHER_BUILDS: usize = 3;

/// This executable's size and modification time, as a folder name.
fn build_id() -> Option<String> {
    let meta = std::fs::metadata(std::env::current_exe().ok()?).ok()?;
    let since = meta
        .modified()
        .ok()?
        .duration_since(std::time::UNIX_EPOCH)
        .ok()?;
    Some(format!("{}-{}", meta.len(), since.as_nanos()))
}

/// 128 bits of everything a model's levels are made from (two SipHash
/// passes with different prefixes).
fn key(
    patches: &[BezierPatch],
    st: &dyn Fn(usize, f32, f32) -> [f32; 2],
    two_sided: bool,
    most_normal_error: f32,
) -> String {
    let half = |prefix: u8| {
        let mut h = std::hash::DefaultHasher::new();
        prefix.hash(&mut h);
        MAGIC.hash(&mut h);
        (two_sided, most_normal_error.to_bits(), patches.len()).hash(&mut h);
        for (k, p) in patches.iter().enumerate() {
            for q in &p.pts {
                q.to_array().map(f32::to_bits).hash(&mut h);
            }
            // The texture coordinates where the welded mesh takes them
            // (81 points fix a bicubic UV patch).
            for j in 0..=SOURCE_GRID {
                for i in 0..=SOURCE_GRID {
                    let (u, v) = (i as f32 / SOURCE_GRID as f32, j as f32 / SOURCE_GRID as f32);
                    st(k, u, v).map(f32::to_bits).hash(&mut h);
                }
            }
        }
        h.finish()
    };
    format!("{:016x}{:016x}", half(0), half(1))
}

/// A model's levels as bytes (little-endian words).
pub fn encode(levels: &[Level]) -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    let u32s = |out: &mut Vec<u8>, v: u32| out.extend(v.to_le_bytes());
    u32s(&mut out, levels.len() as u32);
    for l in levels {
        for f in [l.error, l.normal_error, l.target, l.simplifier_error] {
            u32s(&mut out, f.to_bits());
        }
        u32s(&mut out, l.shading.len() as u32);
        for &(side, e) in &l.shading {
            u32s(&mut out, side.to_bits());
            u32s(&mut out, e.to_bits());
        }
        let m = &l.mesh;
        u32s(&mut out, m.positions.len() as u32);
        for v in 0..m.positions.len() {
            for f in m.positions[v].to_array() {
                u32s(&mut out, f.to_bits());
            }
            for f in m.st[v] {
                u32s(&mut out, f.to_bits());
            }
            u32s(&mut out, m.normals[v].len() as u32);
            for n in &m.normals[v] {
                for f in n.to_array() {
                    u32s(&mut out, f.to_bits());
                }
            }
        }
        u32s(&mut out, m.indices.len() as u32);
        for &i in &m.indices {
            u32s(&mut out, i);
        }
    }
    out
}

/// The levels [`encode`] wrote, or `None` if `bytes` are not exactly that
/// (truncated, another format, an index out of range).
pub fn decode(bytes: &[u8]) -> Option<Vec<Level>> {
    let mut r = Reader(bytes.strip_prefix(MAGIC.as_slice())?);
    let count = r.len()?;
    let mut levels = Vec::with_capacity(count);
    for _ in 0..count {
        let [error, normal_error, target, simplifier_error] =
            [r.f32()?, r.f32()?, r.f32()?, r.f32()?];
        let shading = (0..r.len()?)
            .map(|_| Some((r.f32()?, r.f32()?)))
            .collect::<Option<Vec<_>>>()?;
        let vertices = r.len()?;
        let mut mesh = TriMesh::default();
        for _ in 0..vertices {
            mesh.positions.push(r.vec3()?);
            mesh.st.push([r.f32()?, r.f32()?]);
            let normals = (0..r.len()?)
                .map(|_| r.vec3())
                .collect::<Option<Vec<_>>>()?;
            mesh.normals.push(normals);
        }
        let indices = r.len()?;
        mesh.indices = (0..indices).map(|_| r.u32()).collect::<Option<Vec<_>>>()?;
        let valid = indices % 3 == 0
            && mesh.indices.iter().all(|&i| (i as usize) < vertices)
            && mesh.normals.iter().all(|n| !n.is_empty());
        if !valid {
            return None;
        }
        levels.push(Level {
            mesh,
            error,
            normal_error,
            shading,
            target,
            simplifier_error,
        });
    }
    r.0.is_empty().then_some(levels)
}

struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn u32(&mut self) -> Option<u32> {
        let (word, rest) = self.0.split_first_chunk::<4>()?;
        self.0 = rest;
        Some(u32::from_le_bytes(*word))
    }

    fn f32(&mut self) -> Option<f32> {
        self.u32().map(f32::from_bits)
    }

    fn vec3(&mut self) -> Option<Vec3> {
        Some(Vec3::new(self.f32()?, self.f32()?, self.f32()?))
    }

    /// A count, refused where more bytes than are left would be needed
    /// (a damaged count must not reserve gigabytes).
    fn len(&mut self) -> Option<usize> {
        let n = self.u32()? as usize;
        (n <= self.0.len()).then_some(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lod::mesh::{plain_uv, shapes};

    #[test]
    fn levels_come_back_bit_for_bit() {
        let ball = shapes::rounded_box(4);
        let levels = crate::lod::model_levels(&ball, &plain_uv, false, 0.2);
        assert!(levels.len() >= 2);
        let bytes = encode(&levels);
        let back = decode(&bytes).expect("decodes");
        assert_eq!(encode(&back), bytes);
        assert_eq!(back.len(), levels.len());
        assert_eq!(back[1].mesh.indices, levels[1].mesh.indices);
        // Cut anywhere, or with a word too many, it is refused.
        for cut in [0, 8, 12, bytes.len() / 2, bytes.len() - 1] {
            assert!(decode(&bytes[..cut]).is_none(), "cut at {cut}");
        }
        let mut longer = bytes.clone();
        longer.extend([0, 0, 0, 0]);
        assert!(decode(&longer).is_none());
    }

    #[test]
    fn the_key_changes_with_what_the_levels_are_made_from() {
        let ball = shapes::ball(2);
        let base = key(&ball, &plain_uv, false, 0.1);
        assert_eq!(base, key(&ball, &plain_uv, false, 0.1));
        assert_ne!(base, key(&ball, &plain_uv, true, 0.1));
        assert_ne!(base, key(&ball, &plain_uv, false, 0.2));
        let shifted = |_: usize, u: f32, v: f32| [u + 0.5, v];
        assert_ne!(base, key(&ball, &shifted, false, 0.1));
        let mut moved = ball.clone();
        moved[3].pts[5].z += 1e-6;
        assert_ne!(base, key(&moved, &plain_uv, false, 0.1));
    }

    #[test]
    fn a_second_load_reads_what_the_first_stored() {
        let root = std::env::temp_dir().join(format!("lod-cache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        // Other builds' folders, written a minute apart: storing keeps
        // the three most recent.
        let epoch = std::time::UNIX_EPOCH + std::time::Duration::from_secs(1_800_000_000);
        for k in 0..5u64 {
            let old = root.join(format!("build-{k}"));
            std::fs::create_dir_all(&old).unwrap();
            let when = epoch + std::time::Duration::from_secs(60 * k);
            std::fs::File::open(&old)
                .unwrap()
                .set_modified(when)
                .unwrap();
        }
        let ball = shapes::ball(2);
        let made = std::cell::Cell::new(0);
        let make = || {
            made.set(made.get() + 1);
            crate::lod::model_levels(&ball, &plain_uv, false, 0.2)
        };
        let first = LevelCache::at(&root, "this-build");
        let a = first.levels(&ball, &plain_uv, false, 0.2, make);
        assert_eq!((first.hits.get(), first.stored.get()), (0, 1));
        let left: Vec<bool> = (0..5)
            .map(|k| root.join(format!("build-{k}")).exists())
            .collect();
        assert_eq!(left, [false, false, true, true, true]);
        let second = LevelCache::at(&root, "this-build");
        let b = second.levels(&ball, &plain_uv, false, 0.2, make);
        assert_eq!((second.hits.get(), made.get()), (1, 1));
        assert_eq!(encode(&a), encode(&b));
        // A damaged file is made again and replaced.
        let file = std::fs::read_dir(first.dir())
            .unwrap()
            .next()
            .unwrap()
            .unwrap()
            .path();
        std::fs::write(&file, b"BZLOD001\x05").unwrap();
        let third = LevelCache::at(&root, "this-build");
        let c = third.levels(&ball, &plain_uv, false, 0.2, make);
        assert_eq!(
            (third.hits.get(), third.stored.get(), made.get()),
            (0, 1, 2)
        );
        assert_eq!(encode(&c), encode(&a));
        let _ = std::fs::remove_dir_all(&root);
    }
}
