//! Procedural meshes for the built-in scenes.

use glam::{Vec2, Vec3};
use soft_shadow_core::TriangleMesh;

fn mesh(name: &str, positions: Vec<Vec3>, indices: Vec<[u32; 3]>) -> TriangleMesh {
    TriangleMesh {
        name: name.to_string(),
        positions,
        indices,
    }
}

/// A grid in the plane through `origin` spanned by `u` and `v` (full side vectors), `n x n` cells.
/// Its front (counter-clockwise) face looks along `u x v`.
pub fn quad_grid(name: &str, origin: Vec3, u: Vec3, v: Vec3, n: u32) -> TriangleMesh {
    let n = n.max(1);
    let mut p = Vec::new();
    let mut ix = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            p.push(origin + u * (i as f32 / n as f32) + v * (j as f32 / n as f32));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            ix.push([a, a + 1, a + n + 2]);
            ix.push([a, a + n + 2, a + n + 1]);
        }
    }
    mesh(name, p, ix)
}

/// A horizontal square of side `size` centred on the Y axis at height `y`, `n x n` cells, facing +Y.
pub fn ground(size: f32, y: f32, n: u32) -> TriangleMesh {
    quad_grid(
        "ground",
        Vec3::new(-0.5 * size, y, -0.5 * size),
        Vec3::Z * size,
        Vec3::X * size,
        n,
    )
}

/// A horizontal rectangle `[x0,x1] x [z0,z1]` at height `y`, facing +Y.
pub fn horizontal_rect(name: &str, x: Vec2, z: Vec2, y: f32) -> TriangleMesh {
    quad_grid(
        name,
        Vec3::new(x.x, y, z.x),
        Vec3::Z * (z.y - z.x),
        Vec3::X * (x.y - x.x),
        1,
    )
}

/// An axis-aligned box.
pub fn cuboid(name: &str, center: Vec3, half: Vec3) -> TriangleMesh {
    let c = |sx: f32, sy: f32, sz: f32| center + half * Vec3::new(sx, sy, sz);
    let p = vec![
        c(-1., -1., -1.),
        c(1., -1., -1.),
        c(1., 1., -1.),
        c(-1., 1., -1.),
        c(-1., -1., 1.),
        c(1., -1., 1.),
        c(1., 1., 1.),
        c(-1., 1., 1.),
    ];
    let ix = vec![
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [3, 6, 2],
        [3, 7, 6],
        [0, 4, 7],
        [0, 7, 3],
        [1, 2, 6],
        [1, 6, 5],
    ];
    mesh(name, p, ix)
}

/// A torus around +Y: major radius `r_major`, tube radius `r_minor`; front faces outwards.
pub fn torus(
    center: Vec3,
    r_major: f32,
    r_minor: f32,
    seg_major: u32,
    seg_minor: u32,
) -> TriangleMesh {
    let mut p = Vec::new();
    let mut ix = Vec::new();
    for i in 0..seg_major {
        let a = i as f32 / seg_major as f32 * std::f32::consts::TAU;
        for j in 0..seg_minor {
            let b = j as f32 / seg_minor as f32 * std::f32::consts::TAU;
            let r = r_major + r_minor * b.cos();
            p.push(center + Vec3::new(r * a.cos(), r_minor * b.sin(), r * a.sin()));
        }
    }
    for i in 0..seg_major {
        for j in 0..seg_minor {
            let i1 = (i + 1) % seg_major;
            let j1 = (j + 1) % seg_minor;
            let q = |i: u32, j: u32| i * seg_minor + j;
            ix.push([q(i, j), q(i1, j1), q(i1, j)]);
            ix.push([q(i, j), q(i, j1), q(i1, j1)]);
        }
    }
    mesh("torus", p, ix)
}

/// A patch of a cylinder with axis along Z through `axis_point`, radius `r`, angles (from +Y towards +X)
/// in `[a0, a1]`, length `len`; front faces outwards.
pub fn cylinder_patch(
    axis_point: Vec3,
    r: f32,
    a0: f32,
    a1: f32,
    len: f32,
    segs: u32,
) -> TriangleMesh {
    let mut p = Vec::new();
    let mut ix = Vec::new();
    for i in 0..=segs {
        let a = a0 + (a1 - a0) * i as f32 / segs as f32;
        let off = Vec3::new(a.sin(), a.cos(), 0.0) * r;
        p.push(axis_point + off + Vec3::Z * (-0.5 * len));
        p.push(axis_point + off + Vec3::Z * (0.5 * len));
    }
    for i in 0..segs {
        let a = 2 * i;
        ix.push([a, a + 3, a + 2]);
        ix.push([a, a + 1, a + 3]);
    }
    mesh("cylinder-patch", p, ix)
}

/// A ground strip along -Z from `z = 0` to `z = -length`, width `width`, with cells that grow
/// geometrically (so triangles near the camera stay small), `n` rows.
pub fn graded_strip(width: f32, length: f32, first: f32, n: u32) -> TriangleMesh {
    let ratio = (length / first).powf(1.0 / n as f32);
    let mut zs = vec![0.0f32];
    let mut z = first;
    for _ in 0..n {
        zs.push(-z.min(length));
        z *= ratio;
    }
    let mut p = Vec::new();
    let mut ix = Vec::new();
    for (k, &zk) in zs.iter().enumerate() {
        let w = (0.5 * width).min(0.05 + 0.5 * zk.abs());
        p.push(Vec3::new(-w, 0.0, zk));
        p.push(Vec3::new(w, 0.0, zk));
        if k > 0 {
            let a = 2 * (k as u32 - 1);
            ix.push([a, a + 1, a + 3]);
            ix.push([a, a + 3, a + 2]);
        }
    }
    mesh("graded-strip", p, ix)
}

/// The deterministic generator of procedural scenes.
pub use soft_shadow_core::rng::SplitMix;

/// `count` small random quads of side about `size` inside the box `[lo, hi]`.
pub fn random_quads(count: u32, lo: Vec3, hi: Vec3, size: f32, seed: u64) -> TriangleMesh {
    let mut rng = SplitMix(seed);
    let mut p = Vec::new();
    let mut ix = Vec::new();
    for _ in 0..count {
        let c = lo + (hi - lo) * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let n = Vec3::new(
            rng.next_f32() - 0.5,
            rng.next_f32() + 0.2,
            rng.next_f32() - 0.5,
        )
        .normalize();
        let (t, b) = soft_shadow_core::light::orthonormal_basis(n);
        let s = size * (0.5 + rng.next_f32());
        let base = p.len() as u32;
        for (x, y) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            p.push(c + (t * x + b * y) * s);
        }
        ix.push([base, base + 1, base + 2]);
        ix.push([base, base + 2, base + 3]);
    }
    mesh("foliage", p, ix)
}

/// An ellipsoid with semi-axes `radii` around `center`: `segments` around Y, `rings` from pole
/// to pole (a low-poly sphere at small counts: flat facets, hard silhouette corners); front
/// faces outwards.
pub fn ellipsoid(name: &str, center: Vec3, radii: Vec3, segments: u32, rings: u32) -> TriangleMesh {
    let (segments, rings) = (segments.max(3), rings.max(2));
    let mut p = vec![center + Vec3::Y * radii.y];
    for r in 1..rings {
        let theta = r as f32 / rings as f32 * std::f32::consts::PI;
        for s in 0..segments {
            let phi = s as f32 / segments as f32 * std::f32::consts::TAU;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            p.push(center + d * radii);
        }
    }
    let bottom = p.len() as u32;
    p.push(center - Vec3::Y * radii.y);
    let at = |r: u32, s: u32| 1 + (r - 1) * segments + s % segments;
    let mut ix = Vec::new();
    for s in 0..segments {
        ix.push([0, at(1, s + 1), at(1, s)]);
        ix.push([bottom, at(rings - 1, s), at(rings - 1, s + 1)]);
        for r in 1..rings - 1 {
            ix.push([at(r, s), at(r, s + 1), at(r + 1, s + 1)]);
            ix.push([at(r, s), at(r + 1, s + 1), at(r + 1, s)]);
        }
    }
    mesh(name, p, ix)
}

/// Several meshes as one (indices shifted), named `name`: parts that interpenetrate, as the
/// parts of a modelled figure do.
pub fn merged(name: &str, parts: Vec<TriangleMesh>) -> TriangleMesh {
    let (mut p, mut ix) = (Vec::new(), Vec::new());
    for part in parts {
        let base = p.len() as u32;
        p.extend(part.positions);
        ix.extend(part.indices.iter().map(|t| t.map(|i| i + base)));
    }
    mesh(name, p, ix)
}

/// A low-poly animal (a few hundred triangles) standing on y = 0 around `(x, z)` and facing +X:
/// a faceted body, four tapered legs, a neck and a head, its parts interpenetrating: the flat
/// facets and sharp silhouette corners of the models users bring, which the catalogue's smooth
/// meshes do not have.
pub fn low_poly_animal(name: &str, x: f32, z: f32) -> TriangleMesh {
    let at = |p: Vec3| Vec3::new(x, 0.0, z) + p;
    let mut parts = vec![
        ellipsoid(
            "body",
            at(Vec3::new(0.0, 0.8, 0.0)),
            Vec3::new(0.65, 0.3, 0.28),
            8,
            5,
        ),
        ellipsoid(
            "neck",
            at(Vec3::new(0.62, 1.05, 0.0)),
            Vec3::new(0.14, 0.3, 0.12),
            5,
            3,
        ),
        ellipsoid(
            "head",
            at(Vec3::new(0.85, 1.3, 0.0)),
            Vec3::new(0.25, 0.13, 0.12),
            6,
            3,
        ),
    ];
    for (lx, lz) in [(0.45, 0.16), (0.45, -0.16), (-0.45, 0.16), (-0.45, -0.16)] {
        parts.push(ellipsoid(
            "leg",
            at(Vec3::new(lx, 0.42, lz)),
            Vec3::new(0.07, 0.42, 0.07),
            5,
            2,
        ));
    }
    merged(name, parts)
}

/// A faceted rock: an icosahedron's faces split once (80 triangles), each vertex pushed in or out
/// by up to 30% (`seed`), of radius about `radius` around `center`.
pub fn faceted_rock(name: &str, center: Vec3, radius: f32, seed: u64) -> TriangleMesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut p: Vec<Vec3> = [
        (-1., t, 0.),
        (1., t, 0.),
        (-1., -t, 0.),
        (1., -t, 0.),
        (0., -1., t),
        (0., 1., t),
        (0., -1., -t),
        (0., 1., -t),
        (t, 0., -1.),
        (t, 0., 1.),
        (-t, 0., -1.),
        (-t, 0., 1.),
    ]
    .iter()
    .map(|&(a, b, c)| Vec3::new(a, b, c).normalize())
    .collect();
    let faces: [[u32; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut mids = std::collections::HashMap::new();
    let mut mid = |a: u32, b: u32, p: &mut Vec<Vec3>| {
        *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
            p.push(((p[a as usize] + p[b as usize]) * 0.5).normalize());
            p.len() as u32 - 1
        })
    };
    let mut ix = Vec::new();
    for [a, b, c] in faces {
        let (ab, bc, ca) = (mid(a, b, &mut p), mid(b, c, &mut p), mid(c, a, &mut p));
        ix.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    let mut rng = SplitMix(seed);
    let p = p
        .into_iter()
        .map(|d| center + d * radius * (0.7 + 0.6 * rng.next_f32()))
        .collect();
    mesh(name, p, ix)
}
