"""Batched state validity from Python vs the Rust per-state loop (issue 12 target: >= 80 %).

For each scene and batch size N, times (best of `repeats`):
  - rust loop:   `is_valid` called one state at a time from a Rust loop (`Scene.rust_loop_seconds`),
  - py batched:  one `Scene.is_valid_batch(qs)` call with an (N, dim) float64 array,
  - py per-state: a Python loop calling `Scene.is_valid(q)` N times (for context),
and prints states per second and the batched / Rust ratio.

    python bench/batched_validity.py [N ...]
"""
import sys
import time

import numpy as np

import opengrasp as og

SCENES = ["planar post", "standard (7-DoF stand-in, spheres)", "standard (7-DoF stand-in)", "standard (ARMAR-III kitchen)"]


def best(f, repeats):
    out = float("inf")
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        out = min(out, time.perf_counter() - t)
    return out


def main(sizes):
    print(f"{'scene':38} {'N':>6} {'rust loop /s':>13} {'py batched /s':>14} {'ratio':>6} {'py per-state /s':>16}")
    worst = float("inf")
    for name in SCENES:
        scene = og.Scene(name)
        rng = np.random.default_rng(0)
        lim = scene.limits
        for n in sizes:
            qs = rng.uniform(lim[:, 0], lim[:, 1], size=(n, scene.dim))
            repeats = 7
            rust = min(scene.rust_loop_seconds(qs)[0] for _ in range(repeats))
            batched = best(lambda: scene.is_valid_batch(qs), repeats)
            m = min(n, 2000)
            single = best(lambda: [scene.is_valid(q) for q in qs[:m]], 3) * n / m
            ratio = rust / batched
            worst = min(worst, ratio)
            print(f"{name:38} {n:>6} {n / rust:>13,.0f} {n / batched:>14,.0f} {ratio:>6.1%} {n / single:>16,.0f}")
    print(f"worst batched/Rust ratio: {worst:.1%} (target >= 80 %)")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [1000, 10000])
