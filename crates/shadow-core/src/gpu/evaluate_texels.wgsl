#define_import_path soft_shadow_core::evaluate_texels
#import soft_shadow_core::technique::visibility
#import soft_shadow_core::views::{ViewSelect, view_weight, views_weight}

// The G-buffer pass: the caller's G-buffer in, V out from the technique being evaluated
// (imported as soft_shadow_core::technique), one texel per invocation: world position in xyz with w > 0.5
// where a surface covers the texel, the unit normal facing the camera in xyz. One pass per
// view of the light: the first writes every texel (uncovered ones get V = 1, covered ones
// 1 - views_weight + w V), the others add w V where their weight w is not 0.

@group(1) @binding(0) var receiver_positions: texture_2d<f32>;
@group(1) @binding(1) var receiver_normals: texture_2d<f32>;
@group(1) @binding(2) var receiver_visibility: texture_storage_2d<r32float, read_write>;

@group(2) @binding(0) var<uniform> view_select: ViewSelect;

@compute @workgroup_size(8, 8)
fn evaluate_texels(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(receiver_visibility);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let first = view_select.index == 0u;
    let p = textureLoad(receiver_positions, id.xy, 0);
    if p.w <= 0.5 {
        if first {
            textureStore(receiver_visibility, id.xy, vec4<f32>(1.0, 0.0, 0.0, 1.0));
        }
        return;
    }
    let w = view_weight(view_select, p.xyz);
    var v = 0.0;
    if first {
        v = 1.0 - views_weight(view_select, p.xyz);
    } else {
        if w <= 0.0 {
            return;
        }
        v = textureLoad(receiver_visibility, id.xy).x;
    }
    if w > 0.0 {
        v = v + w * visibility(p.xyz, textureLoad(receiver_normals, id.xy, 0).xyz);
    }
    // Every partial sum lies in [0, 1]; the faces' shares sum to the total only within rounding.
    textureStore(receiver_visibility, id.xy, vec4<f32>(clamp(v, 0.0, 1.0), 0.0, 0.0, 1.0));
}
