//! Seed maps, the vocabulary of the nearest-seed transforms (penumbra-limit's exact feature
//! transform, shadow-width's jump flooding): one `u32` per texel, a seed texel's own coordinates packed
//! ([`pack`]), [`NONE`] elsewhere; a transform's result holds each texel's nearest seed the same
//! way. `gpu/seeds.wgsl` is the GPU side.

/// No seed (heard of yet).
pub const NONE: u32 = u32::MAX;

/// Packs texel coordinates (each below 65536) into one seed value.
pub fn pack(x: u32, y: u32) -> u32 {
    x | (y << 16)
}

/// The texel coordinates of a packed seed.
pub fn unpack(seed: u32) -> (u32, u32) {
    (seed & 0xffff, seed >> 16)
}

/// Squared distance in texels from `(x, y)` to `seed`.
pub fn dist2(x: i32, y: i32, seed: u32) -> i64 {
    let dx = (seed & 0xffff) as i64 - x as i64;
    let dy = (seed >> 16) as i64 - y as i64;
    dx * dx + dy * dy
}
