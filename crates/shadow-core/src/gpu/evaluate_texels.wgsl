#define_import_path soft_shadow_core::evaluate_texels
#import soft_shadow_core::technique::visibility

// The G-buffer pass: the caller's G-buffer in, V out from the technique being evaluated
// (imported as soft_shadow_core::technique), one texel per invocation: world position in xyz with w > 0.5
// where a surface covers the texel, the unit normal facing the camera in xyz. Uncovered texels
// get V = 1.

@group(1) @binding(0) var receiver_positions: texture_2d<f32>;
@group(1) @binding(1) var receiver_normals: texture_2d<f32>;
@group(1) @binding(2) var receiver_visibility: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn evaluate_texels(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(receiver_visibility);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = textureLoad(receiver_positions, id.xy, 0);
    var v = 1.0;
    if p.w > 0.5 {
        v = visibility(p.xyz, textureLoad(receiver_normals, id.xy, 0).xyz);
    }
    textureStore(receiver_visibility, id.xy, vec4<f32>(v, 0.0, 0.0, 1.0));
}
