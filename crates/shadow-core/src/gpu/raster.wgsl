#define_import_path soft_shadow_core::raster

// GPU rasterization shared by every technique: light-space depth maps (reversed Z, depth only)
// and the camera G-buffer (world position + normal). Matches soft_shadow_core::raster on the CPU.

struct ViewUniform {
    view_proj: mat4x4<f32>,
};

@group(0) @binding(0) var<uniform> u: ViewUniform;

@vertex
fn vs_depth(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return u.view_proj * vec4<f32>(position, 1.0);
}

struct GBufferVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

@vertex
fn vs_gbuffer(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> GBufferVarying {
    var out: GBufferVarying;
    out.clip = u.view_proj * vec4<f32>(position, 1.0);
    out.world = position;
    out.normal = normal;
    return out;
}

struct GBufferTargets {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
};

@fragment
fn fs_gbuffer(v: GBufferVarying) -> GBufferTargets {
    var out: GBufferTargets;
    out.position = vec4<f32>(v.world, 1.0);
    out.normal = vec4<f32>(v.normal, 0.0);
    return out;
}
