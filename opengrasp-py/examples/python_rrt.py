"""A Python RRT-Connect-style planner entered into the motion benchmark next to the Rust
reference planners (same validators, metrics, seeds and results file)."""
import sys

import numpy as np
import opengrasp as og


class PyRrt(og.MotionPlanner):
    """Bidirectional RRT with greedy connection; edges checked by Rust (`motion_valid`)."""

    def __init__(self, step=0.2, goal_bias=0.1, max_iterations=20000):
        self.step, self.goal_bias, self.max_iterations = step, goal_bias, max_iterations

    def plan(self, problem):
        goal = problem.goal
        if goal["kind"] != "configuration":
            return None  # this sketch plans to configurations only
        rng = np.random.default_rng(problem.seed)
        lo, hi = problem.limits[:, 0], problem.limits[:, 1]
        trees = [([problem.start], [-1]), ([goal["configuration"]], [-1])]
        for it in range(self.max_iterations):
            if problem.time_left() <= 0:
                return None
            q_rand = trees[1][0][0] if rng.random() < self.goal_bias else rng.uniform(lo, hi)
            a, b = trees[it % 2], trees[(it + 1) % 2]
            new = self._extend(problem, a, q_rand)
            if new is None:
                continue
            # Greedily connect the other tree towards the new node.
            while True:
                reached = self._extend(problem, b, a[0][new])
                if reached is None:
                    break
                if np.linalg.norm(b[0][reached] - a[0][new]) < 1e-9:
                    path_a, path_b = self._path(a, new), self._path(b, reached)
                    path = path_a[::-1] + path_b[1:]
                    if it % 2 == 1:
                        path = path[::-1]
                    return {"path": np.array(path), "iterations": it + 1}
        return None

    def _extend(self, problem, tree, target):
        nodes, parents = tree
        nearest = int(np.argmin(np.linalg.norm(np.asarray(nodes) - target, axis=1)))
        q = nodes[nearest]
        d = np.linalg.norm(target - q)
        q_new = target if d <= self.step else q + (target - q) * (self.step / d)
        if not problem.motion_valid(q, q_new, problem.step):
            return None
        nodes.append(np.asarray(q_new, dtype=float))
        parents.append(nearest)
        return len(nodes) - 1

    @staticmethod
    def _path(tree, i):
        nodes, parents = tree
        out = []
        while i != -1:
            out.append(nodes[i])
            i = parents[i]
        return out


if __name__ == "__main__":
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    results = (
        og.Suite("tiny")  # the Rust reference RRT-Connect and PRM on the planar scene
        .motion_planner(PyRrt, "step = 0.2, goal bias = 0.1")
        .runs(runs).seed(7).run()
    )
    print(results.report())
    results.save("python_rrt.json")
