#define_import_path occlusion_slices::slicing
#import occlusion_slices::frame::{Frame, slice_of, top_code}

// The slicing pass (section 3.4): casters drawn once from the COP; each fragment writes its top
// code (where in the slab it lies, 1 to 255; 0 is empty) into the channel of its slice (and the
// top of the next with the thin-occluder fix) in one of four RGBA8 targets, blended with Max:
// per slice, the texel's topmost fragment. Mirrors slicing.rs.

@group(0) @binding(0) var<uniform> frame: Frame;

@vertex
fn vs_slice(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return frame.view_proj * vec4<f32>(position, 1.0);
}

struct Targets {
    @location(0) s0: vec4<f32>,
    @location(1) s1: vec4<f32>,
    @location(2) s2: vec4<f32>,
    @location(3) s3: vec4<f32>,
};

@fragment
fn fs_slice(@builtin(position) pos: vec4<f32>) -> Targets {
    // View::linear_depth_from_ndc for the reversed-Z perspective of the COP.
    let n = frame.clip_near;
    let f = frame.clip_far;
    let z = n * f / (pos.z * (f - n) + n);
    let k = slice_of(frame, z);
    var m = array<vec4<f32>, 4>();
    m[k / 4u][k % 4u] = f32(top_code(frame, k, z - frame.d)) / 255.0;
    if frame.thin_fix != 0u && k + 1u < frame.slices {
        m[(k + 1u) / 4u][(k + 1u) % 4u] = 1.0;
    }
    return Targets(m[0], m[1], m[2], m[3]);
}
