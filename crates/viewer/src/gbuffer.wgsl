#define_import_path viewer::gbuffer

// The renderer's own G-buffer pass: world position (w = 1 where covered) and the flat normal
// turned towards the camera, the layout `ReceiverTextures` reads.

struct Camera {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
};

@group(0) @binding(0) var<uniform> cam: Camera;

struct Out {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

@vertex
fn vs(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>) -> Out {
    var o: Out;
    o.clip = cam.view_proj * vec4<f32>(p, 1.0);
    o.world = p;
    o.normal = n;
    return o;
}

struct Targets {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
};

@fragment
fn fs(i: Out) -> Targets {
    var n = normalize(i.normal);
    if dot(n, cam.eye.xyz - i.world) < 0.0 {
        n = -n;
    }
    var t: Targets;
    t.position = vec4<f32>(i.world, 1.0);
    t.normal = vec4<f32>(n, 0.0);
    return t;
}
