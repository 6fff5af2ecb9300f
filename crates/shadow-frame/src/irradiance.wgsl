#define_import_path shadow_frame::irradiance
#import shadow_frame::lighting::{LightRecord, light_irradiance}

// The GPU frame's summed output: every light's shadowed irradiance added into one texture over
// the renderer's G-buffer, one pass per light (`gpu_irradiance::record_irradiance`); the pass's
// mode is the light's `terms.z` (0: write 0, 1: add the irradiance, 2: add the irradiance
// times the light's `V`).

@group(0) @binding(0) var<uniform> light: LightRecord;
@group(0) @binding(1) var g_position: texture_2d<f32>;
@group(0) @binding(2) var g_normal: texture_2d<f32>;
@group(0) @binding(3) var light_visibility: texture_2d<f32>;
@group(0) @binding(4) var irradiance: texture_storage_2d<r32float, read_write>;

@compute @workgroup_size(8, 8)
fn add_light(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(irradiance);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let mode = u32(light.terms.z);
    if mode == 0u {
        textureStore(irradiance, id.xy, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let p = textureLoad(g_position, id.xy, 0);
    if p.w <= 0.5 {
        return;
    }
    var e = light_irradiance(light, p.xyz, textureLoad(g_normal, id.xy, 0).xyz);
    if e <= 0.0 {
        return;
    }
    if mode == 2u {
        e = e * textureLoad(light_visibility, id.xy, 0).x;
    }
    let sum = textureLoad(irradiance, id.xy).x + e;
    textureStore(irradiance, id.xy, vec4<f32>(sum, 0.0, 0.0, 1.0));
}
