"""Times Embree (through the `embreex` package, one thread) on the shadow rays that
`cargo run --release -p harness --example ray_rate -- --out DIR` wrote, so the ground truth's
tracer and Embree are measured on exactly the same rays and triangles.

    pip install embreex numpy
    python3 benches/embree_rays.py DIR [REPS]

Prints `scene rays M_rays_per_s_per_core lit_fraction` per scene: the fraction of rays Embree
finds unoccluded, to compare with the one `ray_rate` prints for the same rays.
"""

import sys
import time
from pathlib import Path

import numpy as np
from embreex import rtcore_scene
from embreex.mesh_construction import TriangleMesh


def main():
    folder = Path(sys.argv[1])
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    print("scene rays M_rays_per_s_per_core lit_fraction")
    for tris_file in sorted(folder.glob("*.tris")):
        name = tris_file.stem
        tris = np.fromfile(tris_file, dtype="<f4").reshape(-1, 3, 3)
        rays = np.fromfile(folder / f"{name}.rays", dtype="<f4").reshape(-1, 8)
        scene = rtcore_scene.EmbreeScene()
        TriangleMesh(scene, tris.astype(np.float32))
        # Embree's rays start at t = 0 here: move each origin to its t_min.
        t_min = rays[:, 6:7]
        origins = np.ascontiguousarray(rays[:, 0:3] + rays[:, 3:6] * t_min, dtype=np.float32)
        dirs = np.ascontiguousarray(rays[:, 3:6], dtype=np.float32)
        t_max = rays[:, 7] - rays[:, 6]
        t_max = np.ascontiguousarray(np.where(np.isfinite(t_max), t_max, 1e30), dtype=np.float32)
        times = []
        for _ in range(reps):
            start = time.perf_counter()
            hit = scene.run(origins, dirs, dists=t_max, query="OCCLUDED")
            times.append(time.perf_counter() - start)
        hit = np.asarray(hit)
        lit = float(np.mean(hit < 0))
        rate = len(rays) / float(np.median(times)) / 1e6
        print(f"{name} {len(rays)} {rate:.2f} {lit:.4f}")


if __name__ == "__main__":
    main()
