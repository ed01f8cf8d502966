"""Zoning speed: AMAS on 70 x 70, K-means + connected components on 200 x 200, whole pipeline.

    python runs/bench/zoning_speed.py

Targets (issue): AMAS 70 x 70 < 1 s (Djebali: 160 s); K-means + connected components on
200 x 200 < 0.5 s (Herraz: 0.684 s + up to 15 s on 16 cores); the whole K-means pipeline
with direction optimization < 5 s (Herraz: < 1 min). Best of 5 after a warm-up (numba JIT
and the cutter's profile table are built once per process; their cost is printed apart).
"""

from __future__ import annotations

import time

from evoplan.problems.toolpath import choi_surface
from evoplan.problems.toolpath.plan.zoning.amas import amas_zoning
from evoplan.problems.toolpath.plan.zoning.features import mesh_features
from evoplan.problems.toolpath.plan.zoning.kmeans import kmeans_zoning
from evoplan.problems.toolpath.plan.zoning.plan import plan_zones
from evoplan.problems.toolpath.plan.zoning.stepover import ScallopTarget

def best_of(fn, repeat=5):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out

def main() -> None:
    surface = choi_surface()
    target = ScallopTarget.build(3.175, 1.0, 0.254)
    f70 = mesh_features(surface, 70, 70)
    t0 = time.perf_counter()
    amas_zoning(f70.optimal_feed, k_cmd=1.0, k_lz=0.15, seed=0)
    print(f"AMAS first call (numba JIT included): {time.perf_counter() - t0:.2f} s")
    t, res = best_of(lambda: amas_zoning(f70.optimal_feed, k_cmd=1.0, k_lz=0.15, seed=0))
    print(f"AMAS 70 x 70: {t:.3f} s, {res.labels.max() + 1} zones, {res.cycles} cycles "
          f"(target < 1 s)")
    t, f200 = best_of(lambda: mesh_features(surface, 200, 200))
    print(f"mesh features 200 x 200: {t:.3f} s")
    for k in (3, 6):
        t, z = best_of(lambda: kmeans_zoning(f200, k))
        print(f"K-means K={k} + connected components 200 x 200: {t:.3f} s, {z.max() + 1} zones "
              f"(target < 0.5 s)")
    t0 = time.perf_counter()
    plan_zones(surface, target, "single", mesh=(4, 4))
    print(f"profile table + first plan: {time.perf_counter() - t0:.2f} s")
    for mesh in ((70, 70), (200, 200)):
        t, plan = best_of(lambda: plan_zones(surface, target, "kmeans", mesh=mesh, k=3), 3)
        print(f"whole K-means pipeline {mesh[0]} x {mesh[1]} (samples, features, K=3, "
              f"directions): {t:.2f} s, {len(plan.zones)} zones, total {plan.total_length:.0f} mm, "
              f"{sum(z.evaluations for z in plan.zones)} length evaluations (target < 5 s)")
    t, plan = best_of(lambda: plan_zones(surface, target, "amas", mesh=(70, 70), k_lz=0.15), 3)
    print(f"whole AMAS pipeline 70 x 70: {t:.2f} s, {len(plan.zones)} zones, "
          f"total {plan.total_length:.0f} mm")

if __name__ == "__main__":
    main()
