"""Closest points on a ~100k-triangle reference: libigl's AABB (what ``approximation`` uses,
``dgpc_cli.core.reference.ReferenceSurface``) against trimesh + rtree
(``trimesh.proximity.closest_point``), SPEC §10. Prints one table on stdout.

Run: ``python benchmarks/closest_points_bench.py [--cells 224] [--queries 5000] [--repeat 3]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def wave_mesh(cells: int):
    """A subdivided wave ``z = sin x · cos y`` over [0, 4π]², ``2·cells²`` triangles."""
    u, v = np.meshgrid(np.linspace(0, 4 * np.pi, cells + 1), np.linspace(0, 4 * np.pi, cells + 1),
                       indexing="ij")
    V = np.stack([u.ravel(), v.ravel(), (np.sin(u) * np.cos(v)).ravel()], 1)
    vid = np.arange((cells + 1) ** 2).reshape(cells + 1, cells + 1)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                        np.stack([a, c, d], -1).reshape(-1, 3)])
    return V, F


def best_of(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, default=224, help="grid cells per side (224: 100k tris)")
    ap.add_argument("--queries", type=int, default=5000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()

    import trimesh

    from dgpc_cli.core.reference import ReferenceSurface

    V, F = wave_mesh(args.cells)
    rng = np.random.default_rng(0)
    P = np.column_stack([rng.uniform(0, 4 * np.pi, (args.queries, 2)),
                         rng.normal(0, 0.3, args.queries)])

    build_igl = best_of(lambda: ReferenceSurface(V, F), args.repeat)
    ref = ReferenceSurface(V, F)
    query_igl = best_of(lambda: ref.closest(P), args.repeat)
    p_igl, _ = ref.closest(P)

    def build_tm():
        mesh = trimesh.Trimesh(V, F, process=False)
        _ = mesh.triangles_tree   # the rtree index trimesh.proximity uses
        return mesh

    build_tm_t = best_of(build_tm, args.repeat)
    mesh = build_tm()
    query_tm = best_of(lambda: trimesh.proximity.closest_point(mesh, P), args.repeat)
    p_tm, _, _ = trimesh.proximity.closest_point(mesh, P)
    agree = float(np.abs(np.linalg.norm(p_igl - P, axis=1)
                         - np.linalg.norm(p_tm - P, axis=1)).max())

    print(f"closest points: {len(F):,} triangles, {len(P):,} queries, best of {args.repeat}")
    print(f"{'backend':<22}{'build s':>10}{'query s':>10}{'queries/s':>12}")
    for name, b, q in (("libigl AABB", build_igl, query_igl),
                       ("trimesh + rtree", build_tm_t, query_tm)):
        print(f"{name:<22}{b:>10.4f}{q:>10.4f}{len(P) / q:>12,.0f}")
    print(f"query speed-up libigl / trimesh: {query_tm / query_igl:.1f}x; "
          f"max |distance difference| {agree:.2e}")


if __name__ == "__main__":
    main()
