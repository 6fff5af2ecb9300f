#define_import_path soft_shadow_core::seeds

// Seeds, packed as soft_shadow_core::seeds::pack makes them: x in the low 16 bits, y
// in the high 16, NONE_SEED for no seed. Shared by every shader that floods or reads a flood.

const NONE_SEED: u32 = 0xffffffffu;

fn seed_pack(x: u32, y: u32) -> u32 {
    return x | (y << 16u);
}

// Squared texel distance from (x, y) to seed `s`.
fn seed_dist2(x: i32, y: i32, s: u32) -> i32 {
    let dx = i32(s & 0xffffu) - x;
    let dy = i32(s >> 16u) - y;
    return dx * dx + dy * dy;
}
