"""The standard world's geometry and motion problem sets (JSON and MotionBenchMaker) from Python."""

import json
from pathlib import Path

import numpy as np
import pytest

import opengrasp as og

REPO = Path(__file__).resolve().parents[2]
MBM_CAGE = REPO / "opengrasp-motion" / "tests" / "data" / "mbm" / "panda" / "problems" / "cage_panda"

STOCK_SET = {
    "format": "opengrasp-problem-set",
    "version": 1,
    "name": "stock arm",
    "robot": {"stock": "seven_dof_arm"},
    "problems": [
        {
            "obstacles": [
                {"name": "table", "type": "box", "size": [0.6, 1.2, 0.05], "pose": {"position": [0.65, 0, 0.225]}},
                {"name": "ball", "type": "sphere", "radius": 0.05, "pose": {"position": [0.5, 0.5, 1.2]}},
            ],
            "start": [0, 0, 0, 0, 0, 0, 0],
            "goal": {"configuration": [0.5, 0.3, 0, 0.4, 0, 0, 0]},
        },
        {
            "name": "blocked",
            "obstacles": [{"name": "wall", "type": "box", "size": [0.1, 2.0, 2.0], "pose": {"position": [0.5, 0, 1.0]}}],
            "start": [0, 0, 0, 0, 0, 0, 0],
            "goal": {"configuration": [0.5, 0.3, 0, 0.4, 0, 0, 0]},
        },
    ],
}


@pytest.fixture
def stock_set_path(tmp_path):
    path = tmp_path / "stock.json"
    path.write_text(json.dumps(STOCK_SET))
    return path


def test_json_problem_set_scenes_goals_and_meshes(stock_set_path):
    (pset,) = og.load_problem_sets(stock_set_path)
    assert pset.name == "stock arm"
    assert len(pset) == 2
    assert pset.problem_names == ["0", "blocked"]
    assert len(pset.joint_names) == 7
    goal = pset.goal(0)
    assert goal["kind"] == "configuration"
    np.testing.assert_allclose(goal["configuration"], [0.5, 0.3, 0, 0.4, 0, 0, 0])

    scene = pset.scene(0)
    assert scene.dim == 7
    assert scene.is_valid(scene.start)
    # The 0.6 m box centred at x = 0.65 spans x = 0.35..0.95, z = 0.2..0.25.
    table = next(m for m in pset.meshes(0) if m["name"] == "table")
    v = table["vertices"]
    np.testing.assert_allclose(v.min(axis=0), [0.35, -0.6, 0.2], atol=1e-12)
    np.testing.assert_allclose(v.max(axis=0), [0.95, 0.6, 0.25], atol=1e-12)
    assert table["triangles"].shape[1] == 3 and table["triangles"].max() < len(v)
    ball = next(m for m in pset.meshes(0) if m["name"] == "ball")
    np.testing.assert_allclose(np.linalg.norm(ball["vertices"] - [0.5, 0.5, 1.2], axis=1).max(), 0.05, rtol=1e-9)
    # The robot's links are in the geometry too, and the wall blocks problem 1's goal.
    assert any("/" in m["name"] for m in pset.meshes(1))
    # The same goal is free in problem 0 and inside the wall of problem 1 (clearance 0.39 m at
    # the start).
    blocked = pset.scene(1)
    assert scene.is_valid(goal["configuration"])
    assert not blocked.is_valid(goal["configuration"])
    assert blocked.clearance(blocked.start) == pytest.approx(0.39, abs=0.01)


def test_problem_set_errors_are_typed(stock_set_path, tmp_path):
    (pset,) = og.load_problem_sets(stock_set_path)
    with pytest.raises(og.InvalidInputError, match="out of range"):
        pset.scene(2)
    with pytest.raises(og.InvalidInputError, match="out of range"):
        pset.goal(5)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({**STOCK_SET, "format": "other"}))
    with pytest.raises(og.ModelError, match="format"):
        og.load_problem_sets(bad)
    truncated = tmp_path / "truncated.json"
    truncated.write_text(json.dumps(STOCK_SET)[:200])
    with pytest.raises(og.ModelError):
        og.load_problem_sets(truncated)
    with pytest.raises(og.OpenGraspError):
        og.load_problem_sets(tmp_path / "missing.json")


def test_motionbenchmaker_set_batched_equals_single():
    (pset,) = og.load_problem_sets(MBM_CAGE)
    assert pset.name == "cage_panda"
    assert len(pset) >= 2
    scene = pset.scene(0)
    assert scene.dim == 7
    assert scene.is_valid(scene.start)
    lim = scene.limits
    qs = np.random.default_rng(3).uniform(lim[:, 0], lim[:, 1], size=(64, 7))
    batched = scene.is_valid_batch(qs)
    assert batched.tolist() == [scene.is_valid(q) for q in qs]
    # The cage is a real obstacle: some random states collide, some do not.
    assert 0 < batched.sum() < len(qs)


def test_problem_sets_enter_the_suite(stock_set_path):
    suite = og.Suite().seed(3).problem_sets(stock_set_path).time_limit(2.0).jobs(1)
    assert suite.scene_names == ["stock arm"]
    results = suite.run().to_dict()
    runs = results["motion"]["runs"]
    # RRT-Connect and PRM, one run per problem each.
    assert len(runs) == 4
    assert sorted({r["scene"] for r in runs}) == ["stock arm"]
    assert sorted(r["seed"] for r in runs) == [3, 3, 4, 4]
    with pytest.raises(og.InvalidInputError, match="seed"):
        suite.seed(9)


def test_kitchen_geometry():
    k = og.kitchen()
    names = [m["name"] for m in k["meshes"]]
    floor = k["meshes"][names.index("floor")]["vertices"]
    np.testing.assert_allclose(floor.min(axis=0), [0.0, 0.0, -0.02], atol=1e-12)
    np.testing.assert_allclose(floor.max(axis=0), [6.0, 5.0, 0.0], atol=1e-12)
    assert any(n.startswith("sink") for n in names)
    assert len(k["start_configuration"]) == k["robot"].dof
    sink = k["locations"]["sink"]
    assert sink.shape == (4, 4)
    np.testing.assert_allclose(sink[3], [0, 0, 0, 1])
    # The sink lies between the counters, x in [2.0, 2.6].
    assert 2.0 <= sink[0, 3] <= 2.6
    # Every humanoid link is placed: their meshes carry the robot's name.
    robot_meshes = [n for n in names if n.startswith(k["robot"].name + "/")]
    assert len(robot_meshes) >= 10
