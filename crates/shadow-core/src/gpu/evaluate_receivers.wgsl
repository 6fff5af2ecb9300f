#define_import_path soft_shadow_core::evaluate_receivers
#import soft_shadow_core::technique::visibility

// The blocking evaluation: a batch of receivers, positions and normals in, one V each out,
// from the technique being evaluated (imported as soft_shadow_core::technique).

@group(1) @binding(0) var<storage, read> receiver_positions: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read> receiver_normals: array<vec4<f32>>;
@group(1) @binding(2) var<storage, read_write> receiver_visibility: array<f32>;

@compute @workgroup_size(64)
fn evaluate_receivers(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&receiver_visibility) {
        return;
    }
    receiver_visibility[i] = visibility(receiver_positions[i].xyz, receiver_normals[i].xyz);
}
