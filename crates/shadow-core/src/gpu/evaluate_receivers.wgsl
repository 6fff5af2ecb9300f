#define_import_path soft_shadow_core::evaluate_receivers
#import soft_shadow_core::technique::visibility
#import soft_shadow_core::views::{ViewSelect, view_weight, views_weight}

// The blocking evaluation: a batch of receivers, positions and normals in, one V each out,
// from the technique being evaluated (imported as soft_shadow_core::technique), one pass per
// view of the light: the first writes 1 - views_weight + w V, the others add w V where their
// weight w is not 0.

@group(1) @binding(0) var<storage, read> receiver_positions: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read> receiver_normals: array<vec4<f32>>;
@group(1) @binding(2) var<storage, read_write> receiver_visibility: array<f32>;

@group(2) @binding(0) var<uniform> view_select: ViewSelect;

@compute @workgroup_size(64)
fn evaluate_receivers(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&receiver_visibility) {
        return;
    }
    let p = receiver_positions[i].xyz;
    let w = view_weight(view_select, p);
    var v = 0.0;
    if view_select.index == 0u {
        v = 1.0 - views_weight(view_select, p);
    } else {
        if w <= 0.0 {
            return;
        }
        v = receiver_visibility[i];
    }
    if w > 0.0 {
        v = v + w * visibility(p, receiver_normals[i].xyz);
    }
    // Every partial sum lies in [0, 1]; the faces' shares sum to the total only within rounding.
    receiver_visibility[i] = clamp(v, 0.0, 1.0);
}
