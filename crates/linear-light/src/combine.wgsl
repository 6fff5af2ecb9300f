#define_import_path linear_light::combine

// The visibility channel of one sample (cpu.rs): its lit share plus, for each neighbour whose
// skins cover the texel, the change the skin pass wrote (skins.wgsl).

struct Combine {
    layer: u32,
    has_prev: u32,
    has_next: u32,
    lit: f32,
    piece: f32,
    resolution: u32,
    _pad_a: u32,
    _pad_b: u32,
};

const NO_SKIN: f32 = -1.0;

@group(0) @binding(0) var<uniform> cb: Combine;
@group(0) @binding(1) var prev_skin: texture_2d<f32>;
@group(0) @binding(2) var next_skin: texture_2d<f32>;
@group(0) @binding(3) var channel: texture_storage_2d_array<r32float, write>;

@compute @workgroup_size(8, 8)
fn combine(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= cb.resolution || id.y >= cb.resolution {
        return;
    }
    var c = cb.lit;
    if cb.has_prev == 1u {
        let v = textureLoad(prev_skin, id.xy, 0).x;
        if v != NO_SKIN {
            c += v;
        }
    }
    if cb.has_next == 1u {
        let v = textureLoad(next_skin, id.xy, 0).x;
        if v != NO_SKIN {
            c += v;
        }
    }
    textureStore(channel, id.xy, i32(cb.layer), vec4<f32>(c, 0.0, 0.0, 0.0));
}
