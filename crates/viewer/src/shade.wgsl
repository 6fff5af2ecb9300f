#define_import_path example_renderer::shade

// The renderer's own shading pass: Lambert, one rectangular area light, times the technique's V.
// Mirrors `shade::radiance` in Rust.

const MAX_SAMPLES: u32 = 64u;

struct Shade {
    // Light sample positions (xyz); w unused.
    samples: array<vec4<f32>, 64>,
    // Emission normal in xyz, sample count in w.
    light_normal: vec4<f32>,
    // Intensity (light area over sample count folded in), ambient, albedo, background.
    terms: vec4<f32>,
};

@group(0) @binding(0) var<uniform> sh: Shade;
@group(0) @binding(1) var g_position: texture_2d<f32>;
@group(0) @binding(2) var g_normal: texture_2d<f32>;
@group(0) @binding(3) var g_visibility: texture_2d<f32>;
@group(0) @binding(4) var color: texture_storage_2d<rgba8unorm, write>;

// The light's unshadowed irradiance, each sample clipped to the receiver's horizon and to the
// light's front.
fn unshadowed(p: vec3<f32>, n: vec3<f32>) -> f32 {
    var e = 0.0;
    let count = min(u32(sh.light_normal.w), MAX_SAMPLES);
    for (var k = 0u; k < count; k++) {
        let d = sh.samples[k].xyz - p;
        let r2 = max(dot(d, d), 1.0e-8);
        let l = d * inverseSqrt(r2);
        e += max(dot(n, l), 0.0) * max(-dot(sh.light_normal.xyz, l), 0.0) / r2;
    }
    return e;
}

@compute @workgroup_size(8, 8)
fn shade(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = textureLoad(g_position, id.xy, 0);
    var c = sh.terms.w;
    if p.w > 0.5 {
        let n = textureLoad(g_normal, id.xy, 0).xyz;
        let v = textureLoad(g_visibility, id.xy, 0).x;
        c = sh.terms.z * (sh.terms.y + sh.terms.x * unshadowed(p.xyz, n) * v);
    }
    c = clamp(c, 0.0, 1.0);
    textureStore(color, id.xy, vec4<f32>(c, c, c, 1.0));
}
