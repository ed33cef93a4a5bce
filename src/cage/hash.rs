//! A fast hasher for the converter's maps keyed by vertex and edge
//! indices. The standard library's SipHash guards against crafted keys,
//! which these maps never see, and was a quarter of an isolated import's
//! time (`perf`, the car at `isolate = 2`). Nothing depends on the maps'
//! iteration order (it is random per process with SipHash too).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A map keyed by small integers (vertex and edge indices).
pub type IndexMap<K, V> = HashMap<K, V, BuildHasherDefault<IndexHasher>>;

/// Multiply-rotate hashing of whole words (FxHash's scheme): one multiply
/// per word, its high bits well mixed for the table's control bytes.
#[derive(Default, Clone, Copy)]
pub struct IndexHasher(u64);

impl IndexHasher {
    const K: u64 = 0x517c_c1b7_2722_0a95;

    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(Self::K);
    }
}

impl Hasher for IndexHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
    }

    fn write_u32(&mut self, n: u32) {
        self.add(u64::from(n));
    }

    fn write_u64(&mut self, n: u64) {
        self.add(n);
    }

    fn write_usize(&mut self, n: usize) {
        self.add(n as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}
