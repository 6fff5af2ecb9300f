#define_import_path shadow_frame::lighting

// A light's unshadowed irradiance at a receiver, as the frame's summed output weighs it
// (`lighting::LightRecord::irradiance` in Rust): a point of radiant intensity at the light's
// centre (the distance kept at least the light's size, a one-sided light also weighed by the
// cosine at its emitting plane), or a distant light's irradiance at normal incidence, faded to 0
// at its range by `(1 - x²)²` of x, the squared distance over the squared range. No bindings:
// a renderer's own shader imports it.

// One light (`lighting::LightRecord`).
struct LightRecord {
    // Centre (w = 1), or the unit direction towards a distant light (w = 0).
    position: vec4<f32>,
    // Unit emission normal of a one-sided light (zero: every direction); the light's size² (w).
    front: vec4<f32>,
    // Radiant intensity (or a distant light's irradiance), 1 / range² (0: no range), the pass's
    // mode (0: write 0, 1: add the irradiance, 2: add the irradiance times `V`), unused.
    terms: vec4<f32>,
};

// `l`'s unshadowed irradiance at `p` with unit normal `n`.
fn light_irradiance(l: LightRecord, p: vec3<f32>, n: vec3<f32>) -> f32 {
    if l.position.w == 0.0 {
        return l.terms.x * max(dot(n, l.position.xyz), 0.0);
    }
    let d = l.position.xyz - p;
    let d2 = dot(d, d);
    let x = d2 * l.terms.y;
    if x >= 1.0 {
        return 0.0;
    }
    let r2 = max(max(d2, l.front.w), 1.0e-6);
    let to_light = d * inverseSqrt(r2);
    var at_light = 1.0;
    if dot(l.front.xyz, l.front.xyz) > 0.0 {
        at_light = max(-dot(l.front.xyz, to_light), 0.0);
    }
    let window = (1.0 - x * x) * (1.0 - x * x);
    return l.terms.x * max(dot(n, to_light), 0.0) * at_light / r2 * window;
}

