#define_import_path linear_light::find_skins
#import linear_light::grid::{grid_triangle, pair, quad_touches_edge, samples}

// Lists the quads of a source map that hold a skin (skins.rs::skins), for the indirect draw of
// skins.wgsl: one invocation per quad, appended with an atomic counter that is also the draw's
// vertex count (6 per quad).

@group(0) @binding(3) var<storage, read_write> quads: array<u32>;
@group(0) @binding(4) var<storage, read_write> draw: array<atomic<u32>, 4>;

@compute @workgroup_size(8, 8)
fn find_skins(@builtin(global_invocation_id) id: vec3<u32>) {
    let resolution = samples[pair.src].map.resolution;
    if resolution < 2u || id.x >= resolution - 1u || id.y >= resolution - 1u {
        return;
    }
    let qx = i32(id.x);
    let qy = i32(id.y);
    if !quad_touches_edge(qx, qy) {
        return;
    }
    if !(grid_triangle(qx, qy, 0u).skin || grid_triangle(qx, qy, 1u).skin) {
        return;
    }
    let slot = atomicAdd(&draw[0], 6u) / 6u;
    quads[slot] = id.y * (resolution - 1u) + id.x;
}
