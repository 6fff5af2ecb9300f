#define_import_path viewer::lamps
#import shadow_frame::lighting::{LightRecord, light_irradiance}

// The shading of a scene of many lamps: every lamp's irradiance as the frame pipeline's summed
// output weighs it (`shadow_frame::lighting`: the shared budget's estimate faded to 0 at the
// lamp's range), times its `V` from its layer (lamp k's is layer k) of the texture the frame
// pipeline wrote. Mirrors `shade::LampShade` in Rust.

// `count` lamps; `mode` 0 shaded, 1 the lamps' V weighed by their light; `terms`: exposure,
// ambient, albedo, background.
struct LampsDisplay {
    count: u32,
    mode: u32,
    pad0: u32,
    pad1: u32,
    terms: vec4<f32>,
};

@group(0) @binding(0) var<storage, read> lamps: array<LightRecord>;
@group(0) @binding(1) var<uniform> display: LampsDisplay;
@group(0) @binding(2) var g_position: texture_2d<f32>;
@group(0) @binding(3) var g_normal: texture_2d<f32>;
@group(0) @binding(4) var g_visibility: texture_2d_array<f32>;
@group(0) @binding(5) var color: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn shade(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = textureLoad(g_position, id.xy, 0);
    var rgb = vec3<f32>(display.terms.w);
    if p.w > 0.5 {
        let n = textureLoad(g_normal, id.xy, 0).xyz;
        var lit = 0.0;
        var shadowed = 0.0;
        for (var k = 0u; k < display.count; k++) {
            let e = light_irradiance(lamps[k], p.xyz, n);
            if e > 0.0 {
                let v = textureLoad(g_visibility, id.xy, k, 0).x;
                lit += e;
                shadowed += e * v;
            }
        }
        if display.mode == 1u {
            rgb = vec3<f32>(select(1.0, shadowed / lit, lit > 0.0));
        } else {
            rgb = vec3<f32>(display.terms.z * (display.terms.y + display.terms.x * shadowed));
        }
    }
    rgb = clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0));
    textureStore(color, id.xy, vec4<f32>(rgb, 1.0));
}
