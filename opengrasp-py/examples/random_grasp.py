"""A random-shooting grasp planner in Python, entered into the standard grasp benchmark."""
import numpy as np
import opengrasp as og


class RandomShooting(og.GraspPlanner):
    """Palm on random surface points, approaching along the inward normal, random roll."""

    def __init__(self, n=32):
        self.n = n

    def plan(self, request):
        rng = np.random.default_rng(request.seed)
        v, t = request.vertices, request.triangles
        out = []
        for tri in t[rng.integers(len(t), size=self.n)]:
            a, b, c = v[tri]
            normal = np.cross(b - a, c - a)
            approach = -normal / np.linalg.norm(normal)  # towards the object
            pose = og.palm_pose(request.hand, (a + b + c) / 3, approach, rng.normal(size=3))
            out.append(og.GraspCandidate(pose, approach))
        return out


if __name__ == "__main__":
    results = (
        og.Suite().grasp_planner(RandomShooting(), "n = 32")
        .hands(["barrett"]).objects(["salt_can", "white_cup"]).seed(1).run()
    )
    print(results.report())
    results.save("random_grasp.json")
