//! What a scene may hold: the bounds that f32 arithmetic and the
//! subdivision kernel's counters set. The readers that refuse what is past
//! them (patch files, cages, scene files, the geometry builder) share them
//! from here, below all of them.

/// Largest absolute world coordinate accepted. The criterion multiplies up
/// to sixth powers of lengths; this keeps them far from f32 overflow.
pub const MAX_COORD: f32 = 1.0e6;

/// Most base patches a scene may have: the subdivision kernel counts the
/// items in flight, base patches included, in 24 bits.
pub const MAX_BASE_PATCHES: u64 = crate::constants::IN_FLIGHT_MASK as u64;

/// Bytes per base patch on the GPU: 16 control points of 3 f32 and a
/// flags word.
pub const GEOMETRY_BYTES_PER_PATCH: u64 = 16 * 3 * 4 + 4;
