//! Exact proof that a receiver sees the whole light: no caster triangle crosses the convex hull
//! of the ray origin and the light's outline ([`soft_shadow_core::Light::outline`]).
//!
//! The hull is tested against the BVH's nodes by its face planes and against each candidate
//! triangle by the separating axis theorem (face normals of both, cross products of their
//! edges). Every doubt counts as a crossing: a separation must clear a tolerance, and a
//! degenerate hull is never certified. A certified receiver has `V = 1` exactly (error 0); any
//! other goes to the Monte Carlo estimate, so a wrong "crossing" only costs rays.

use glam::{Vec3, Vec3A};
use obvhs::bvh2::Bvh2;
use obvhs::triangle::Triangle;

/// The hull of an apex and a convex outline (1 point: a segment; 2: a triangle; more: a pyramid).
pub struct Hull {
    points: Vec<Vec3A>,
    edges: Vec<Vec3A>,
    planes: Vec<(Vec3A, f32)>,
    /// The hull between two parallel planes per axis (axis, low, high): its faces, or for a
    /// flat hull its plane and in-plane edge normals. [`Hull::near`] tests only these.
    slabs: Vec<(Vec3A, f32, f32)>,
    lo: Vec3A,
    hi: Vec3A,
    tol: f32,
}

impl Hull {
    /// The hull of `apex` and the convex, ordered `outline` (at least one point).
    pub fn new(apex: Vec3, outline: &[Vec3]) -> Self {
        let apex = Vec3A::from(apex);
        let base: Vec<Vec3A> = outline.iter().map(|&q| Vec3A::from(q)).collect();
        let mut points = vec![apex];
        points.extend_from_slice(&base);
        let scale = points
            .iter()
            .fold(0.0f32, |m, p| m.max(p.abs().max_element()))
            + (base[0] - apex).length();
        let tol = 1e-6 * scale.max(1e-12);
        let mut edges: Vec<Vec3A> = base.iter().map(|&q| q - apex).collect();
        let k = base.len();
        if k >= 2 {
            for i in 0..k {
                let e = base[(i + 1) % k] - base[i];
                if k > 2 || i == 0 {
                    edges.push(e);
                }
            }
        }
        // Face planes (outward normals) of a pyramid; only a proper pyramid has them.
        let mut planes = Vec::new();
        if k >= 3 {
            let centroid = points.iter().copied().sum::<Vec3A>() / points.len() as f32;
            let mut add = |a: Vec3A, b: Vec3A, c: Vec3A| {
                let n = (b - a).cross(c - a);
                if n.length_squared() > 0.0 {
                    let n = n.normalize();
                    let n = if n.dot(centroid - a) > 0.0 { -n } else { n };
                    planes.push((n, n.dot(a)));
                }
            };
            for i in 0..k {
                add(apex, base[i], base[(i + 1) % k]);
            }
            add(base[0], base[1], base[2]);
        }
        let mut slabs: Vec<(Vec3A, f32, f32)> = planes
            .iter()
            .map(|&(n, d)| (n, f32::NEG_INFINITY, d))
            .collect();
        if planes.is_empty() && edges.len() >= 2 {
            let hn = edges[0].cross(edges[1]).normalize_or_zero();
            let ring = [points[0], points[1], points[2], points[0]];
            let axes = std::iter::once(hn).chain(ring.windows(2).map(|w| (w[1] - w[0]).cross(hn)));
            for axis in axes {
                if axis.length_squared() > 0.0 {
                    let (a, b) = Self::range(&points, axis);
                    slabs.push((axis, a, b));
                }
            }
        }
        let lo = points
            .iter()
            .fold(Vec3A::splat(f32::INFINITY), |m, p| m.min(*p));
        let hi = points
            .iter()
            .fold(Vec3A::splat(f32::NEG_INFINITY), |m, p| m.max(*p));
        Self {
            points,
            edges,
            planes,
            slabs,
            lo,
            hi,
            tol,
        }
    }

    /// Whether an axis-aligned box may touch the hull (false only when clearly apart).
    fn may_touch_box(&self, min: Vec3A, max: Vec3A) -> bool {
        if (min.cmpgt(self.hi + self.tol) | max.cmplt(self.lo - self.tol)).any() {
            return false;
        }
        for &(n, d) in &self.planes {
            // The box corner furthest against the outward normal.
            let c = Vec3A::select(n.cmpgt(Vec3A::ZERO), min, max);
            if n.dot(c) > d + self.tol {
                return false;
            }
        }
        true
    }

    fn range(points: &[Vec3A], axis: Vec3A) -> (f32, f32) {
        points
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
                let x = axis.dot(*p);
                (lo.min(x), hi.max(x))
            })
    }

    /// Whether the triangle may touch the hull (false only when an axis separates them clearly).
    /// Runs once per candidate triangle per receiver: no allocation.
    pub fn may_touch(&self, t: &Triangle) -> bool {
        let tri = [t.v0, t.v1, t.v2];
        let te = [t.v1 - t.v0, t.v2 - t.v1, t.v0 - t.v2];
        let tn = te[0].cross(te[1]);
        let separates = |axis: Vec3A| {
            let len = axis.length();
            if len.is_nan() || len <= 1e-20 {
                return false;
            }
            let axis = axis / len;
            let (a0, a1) = Self::range(&self.points, axis);
            let (b0, b1) = Self::range(&tri, axis);
            a1 < b0 - self.tol || b1 < a0 - self.tol
        };
        if separates(tn) || self.planes.iter().any(|(n, _)| separates(*n)) {
            return false;
        }
        for &e in &self.edges {
            if te.iter().any(|&f| separates(e.cross(f))) || separates(e.cross(tn)) {
                return false;
            }
        }
        if self.planes.is_empty() && self.edges.len() >= 2 {
            // A flat hull (segment light): its plane's normal and in-plane edge normals.
            let hn = self.edges[0].cross(self.edges[1]);
            if separates(hn)
                || self.edges.iter().any(|&e| separates(e.cross(hn)))
                || te.iter().any(|&f| separates(f.cross(hn)))
            {
                return false;
            }
        }
        true
    }

    /// Whether no triangle of `bvh` may touch the hull.
    pub fn clear_of(&self, bvh: &Bvh2, tris: &[Triangle]) -> bool {
        self.visit(bvh, tris, Self::may_touch, |_| false)
    }

    /// Whether the triangle may touch the hull by a looser, cheaper test than
    /// [`Hull::may_touch`]: its bounds, and the hull's slabs as separating axes. Every triangle
    /// that touches the hull passes (a doubt passes too).
    pub fn near(&self, t: &Triangle) -> bool {
        let lo = t.v0.min(t.v1).min(t.v2);
        let hi = t.v0.max(t.v1).max(t.v2);
        if (lo.cmpgt(self.hi + self.tol) | hi.cmplt(self.lo - self.tol)).any() {
            return false;
        }
        self.slabs.iter().all(|&(n, a, b)| {
            let (x, y, z) = (n.dot(t.v0), n.dot(t.v1), n.dot(t.v2));
            x.min(y).min(z) <= b + self.tol && x.max(y).max(z) >= a - self.tol
        })
    }

    /// Appends to `out` the index of every triangle of `bvh` that is [`Hull::near`] the hull,
    /// in the BVH's leaf order.
    pub fn near_of(&self, bvh: &Bvh2, tris: &[Triangle], out: &mut Vec<u32>) {
        self.visit(bvh, tris, Self::near, |i| {
            out.push(i);
            true
        });
    }

    /// Calls `found` with each triangle of `bvh` that passes `test` until it returns false;
    /// returns whether it never did.
    fn visit(
        &self,
        bvh: &Bvh2,
        tris: &[Triangle],
        test: impl Fn(&Self, &Triangle) -> bool,
        mut found: impl FnMut(u32) -> bool,
    ) -> bool {
        if bvh.nodes.is_empty() {
            return true;
        }
        let mut stack = vec![0u32];
        while let Some(i) = stack.pop() {
            let node = &bvh.nodes[i as usize];
            let b = node.aabb();
            if !self.may_touch_box(b.min, b.max) {
                continue;
            }
            if node.is_leaf() {
                let first = node.first_index as usize;
                for k in first..first + node.prim_count as usize {
                    let id = bvh.primitive_indices[k];
                    if test(self, &tris[id as usize]) && !found(id) {
                        return false;
                    }
                }
            } else {
                stack.push(node.first_index);
                stack.push(node.first_index + 1);
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(a: Vec3, b: Vec3, c: Vec3) -> Triangle {
        Triangle {
            v0: a.into(),
            v1: b.into(),
            v2: c.into(),
        }
    }

    #[test]
    fn a_triangle_inside_the_pyramid_touches_and_one_beside_it_does_not() {
        let square = [
            Vec3::new(-1.0, 2.0, -1.0),
            Vec3::new(1.0, 2.0, -1.0),
            Vec3::new(1.0, 2.0, 1.0),
            Vec3::new(-1.0, 2.0, 1.0),
        ];
        let h = Hull::new(Vec3::ZERO, &square);
        let small = 0.05;
        let inside = tri(
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(small, 1.0, 0.0),
            Vec3::new(0.0, 1.0, small),
        );
        assert!(h.may_touch(&inside));
        // At height 1 the pyramid spans |x| <= 0.5: a triangle at x in [0.6, 0.7] is beside it.
        let beside = tri(
            Vec3::new(0.6, 1.0, 0.0),
            Vec3::new(0.7, 1.0, 0.0),
            Vec3::new(0.6, 1.0, 0.1),
        );
        assert!(!h.may_touch(&beside));
        // A long thin triangle piercing the side face touches.
        let pierce = tri(
            Vec3::new(0.3, 1.0, 0.0),
            Vec3::new(3.0, 1.0, 0.0),
            Vec3::new(3.0, 1.0, 0.01),
        );
        assert!(h.may_touch(&pierce));
    }

    #[test]
    fn a_segment_hull_sees_only_what_crosses_its_plane_triangle() {
        let h = Hull::new(
            Vec3::ZERO,
            &[Vec3::new(-1.0, 2.0, 0.0), Vec3::new(1.0, 2.0, 0.0)],
        );
        let crossing = tri(
            Vec3::new(0.0, 1.0, -0.1),
            Vec3::new(0.1, 1.0, 0.1),
            Vec3::new(-0.1, 1.0, 0.1),
        );
        assert!(h.may_touch(&crossing));
        let off = tri(
            Vec3::new(0.0, 1.0, 0.2),
            Vec3::new(0.1, 1.0, 0.3),
            Vec3::new(-0.1, 1.0, 0.3),
        );
        assert!(!h.may_touch(&off));
    }
}
