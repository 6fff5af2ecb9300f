#define_import_path viewer::shade
#import soft_shadow_core::views::{ViewSelect, view_weight}

// The renderer's own shading and display pass: Lambert, one light sampled at up to 64 points,
// times the technique's V; or V itself, or V against the reference. Mirrors `shade::radiance`
// in Rust.

const MAX_SAMPLES: u32 = 64u;

struct Shade {
    // Light sample positions (xyz, w = 1), or the direction towards a distant light (w = 0).
    samples: array<vec4<f32>, 64>,
    // Emission normal in xyz (zero: every direction), sample count in w.
    light_normal: vec4<f32>,
    // Intensity (light area over sample count folded in), ambient, albedo, background.
    terms: vec4<f32>,
};

// What the pass writes: `mode` 0 shaded, 1 V, 2 V against the reference, 3 the light's views;
// pixels from column `split` on show the second technique's V; `reference` 1 when the
// reference texture holds one; `views`, how a receiver picks its view of the light.
struct Display {
    mode: u32,
    split: u32,
    reference: u32,
    line: u32,
    views: ViewSelect,
};

// The colour of view i (`view_colour` in renderer.rs), cycling after six.
fn view_colour(i: u32) -> vec3<f32> {
    var colours = array<vec3<f32>, 6>(
        vec3<f32>(0.9, 0.2, 0.15),
        vec3<f32>(0.2, 0.75, 0.25),
        vec3<f32>(0.2, 0.4, 0.95),
        vec3<f32>(0.95, 0.85, 0.2),
        vec3<f32>(0.85, 0.3, 0.85),
        vec3<f32>(0.2, 0.85, 0.9),
    );
    return colours[i % 6u];
}

// The colour of the views p reads, each by its weight (white where none does: a cube direction
// whose face holds no caster).
fn views_colour(p: vec3<f32>) -> vec3<f32> {
    var s = display.views;
    var rgb = vec3<f32>(0.0);
    var total = 0.0;
    for (var i = 0u; i < s.count; i++) {
        s.index = i;
        let w = view_weight(s, p);
        rgb += w * view_colour(i);
        total += w;
    }
    return rgb + vec3<f32>(max(1.0 - total, 0.0));
}

@group(0) @binding(0) var<uniform> sh: Shade;
@group(0) @binding(1) var g_position: texture_2d<f32>;
@group(0) @binding(2) var g_normal: texture_2d<f32>;
@group(0) @binding(3) var g_visibility: texture_2d<f32>;
@group(0) @binding(4) var color: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(5) var<uniform> display: Display;
@group(0) @binding(6) var g_visibility_b: texture_2d<f32>;
@group(0) @binding(7) var g_reference: texture_2d<f32>;

// The light's unshadowed irradiance, each sample clipped to the receiver's horizon and to the
// light's front.
fn unshadowed(p: vec3<f32>, n: vec3<f32>) -> f32 {
    var e = 0.0;
    let count = min(u32(sh.light_normal.w), MAX_SAMPLES);
    let oriented = dot(sh.light_normal.xyz, sh.light_normal.xyz) > 0.0;
    for (var k = 0u; k < count; k++) {
        let s = sh.samples[k];
        if s.w == 0.0 {
            e += max(dot(n, s.xyz), 0.0);
            continue;
        }
        let d = s.xyz - p;
        let r2 = max(dot(d, d), 1.0e-8);
        let l = d * inverseSqrt(r2);
        var front = 1.0;
        if oriented {
            front = max(-dot(sh.light_normal.xyz, l), 0.0);
        }
        e += max(dot(n, l), 0.0) * front / r2;
    }
    return e;
}

@compute @workgroup_size(8, 8)
fn shade(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    if display.line == 1u && (id.x == display.split || id.x + 1u == display.split) {
        textureStore(color, id.xy, vec4<f32>(1.0, 0.85, 0.2, 1.0));
        return;
    }
    let p = textureLoad(g_position, id.xy, 0);
    var rgb = vec3<f32>(sh.terms.w);
    if p.w > 0.5 {
        let n = textureLoad(g_normal, id.xy, 0).xyz;
        var v = textureLoad(g_visibility, id.xy, 0).x;
        if id.x >= display.split {
            v = textureLoad(g_visibility_b, id.xy, 0).x;
        }
        let lit = sh.terms.x * unshadowed(p.xyz, n);
        let c = sh.terms.z * (sh.terms.y + lit * v);
        if display.mode == 0u {
            rgb = vec3<f32>(c);
        } else if display.mode == 1u {
            rgb = vec3<f32>(v);
        } else if display.mode == 3u {
            rgb = views_colour(p.xyz) * min(0.35 + 0.65 * c, 1.0);
        } else {
            // Grey: what the lit scene looks like, dimmed; red where V is darker than the
            // reference (false shadow), blue where lighter (light leaking).
            rgb = vec3<f32>(0.25 + 0.35 * clamp(sh.terms.y + lit, 0.0, 1.0));
            if display.reference == 1u {
                let rs = textureDimensions(g_reference);
                let q = min(id.xy * rs / size, rs - vec2<u32>(1u));
                let r = textureLoad(g_reference, q, 0).x;
                if r >= 0.0 {
                    let d = clamp(v - r, -1.0, 1.0);
                    let a = min(abs(d) * 2.0, 1.0);
                    let hue = select(vec3<f32>(1.0, 0.15, 0.1), vec3<f32>(0.2, 0.45, 1.0), d > 0.0);
                    rgb = mix(rgb, hue, a);
                }
            }
        }
    }
    rgb = clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0));
    textureStore(color, id.xy, vec4<f32>(rgb, 1.0));
}
