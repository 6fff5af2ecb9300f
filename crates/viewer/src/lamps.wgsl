#define_import_path viewer::lamps

// The shading of a scene of many lamps: every lamp weighed as the frame pipeline's shared budget
// weighs it (`shadow_frame::budget::irradiance_estimate`: a point of radiant intensity at the
// lamp's centre, the distance kept at least the lamp's size, a one-sided lamp's cosine at its
// emitting plane; a distant light as irradiance at normal incidence), faded to 0 at its
// influence radius, times its `V` from its layer (lamp k's is layer k) of the texture the frame
// pipeline wrote. Mirrors `shade::LampShade` in Rust.

struct Lamp {
    // Centre (xyz) and influence radius (w); for a distant light the unit direction towards
    // it, and w < 0.
    centre: vec4<f32>,
    // Emission normal of a one-sided lamp (xyz, unit; zero: every direction), size² (w).
    front: vec4<f32>,
    // Radiant intensity (x).
    terms: vec4<f32>,
};

// `count` lamps; `mode` 0 shaded, 1 the lamps' V weighed by their light; `terms`: exposure,
// ambient, albedo, background.
struct LampsDisplay {
    count: u32,
    mode: u32,
    pad0: u32,
    pad1: u32,
    terms: vec4<f32>,
};

@group(0) @binding(0) var<storage, read> lamps: array<Lamp>;
@group(0) @binding(1) var<uniform> display: LampsDisplay;
@group(0) @binding(2) var g_position: texture_2d<f32>;
@group(0) @binding(3) var g_normal: texture_2d<f32>;
@group(0) @binding(4) var g_visibility: texture_2d_array<f32>;
@group(0) @binding(5) var color: texture_storage_2d<rgba8unorm, write>;

// Lamp `k`'s unshadowed irradiance at `p` with unit normal `n` (0 beyond its influence).
fn lamp_irradiance(k: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let lamp = lamps[k];
    if lamp.centre.w < 0.0 {
        return lamp.terms.x * max(dot(n, lamp.centre.xyz), 0.0);
    }
    let d = lamp.centre.xyz - p;
    let d2 = dot(d, d);
    if d2 > lamp.centre.w * lamp.centre.w {
        return 0.0;
    }
    let r2 = max(max(d2, lamp.front.w), 1.0e-6);
    let l = d * inverseSqrt(r2);
    var at_light = 1.0;
    if dot(lamp.front.xyz, lamp.front.xyz) > 0.0 {
        at_light = max(-dot(lamp.front.xyz, l), 0.0);
    }
    // Faded to 0 at the range (`range_window`), so the range draws no edge.
    let x = d2 / (lamp.centre.w * lamp.centre.w);
    let window = (1.0 - x * x) * (1.0 - x * x);
    return lamp.terms.x * max(dot(n, l), 0.0) * at_light / r2 * window;
}

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
            let e = lamp_irradiance(k, p.xyz, n);
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
