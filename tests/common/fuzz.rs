//! Mangled inputs for parsers that must never panic.

use rand::rngs::SmallRng;
use rand::Rng;

/// `base` with one to three bytes overwritten, removed or inserted at
/// random places, the new bytes drawn from `alphabet` (ASCII).
pub fn mangle(rng: &mut SmallRng, base: &str, alphabet: &[u8]) -> String {
    let mut bytes = base.as_bytes().to_vec();
    for _ in 0..rng.random_range(1..4) {
        let at = rng.random_range(0..bytes.len());
        match rng.random_range(0..3) {
            0 => bytes[at] = alphabet[rng.random_range(0..alphabet.len())],
            1 => {
                bytes.remove(at);
            }
            _ => bytes.insert(at, alphabet[rng.random_range(0..alphabet.len())]),
        }
    }
    String::from_utf8(bytes).unwrap()
}
