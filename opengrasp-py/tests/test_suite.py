"""Python planners in the standard suite: same evaluator, validators, metrics, results file,
reports and high-score submission as Rust planners."""

import json
import pathlib
import sys

import numpy as np
import pytest

import opengrasp as og

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "examples"))
from python_rrt import PyRrt  # noqa: E402
from random_grasp import RandomShooting  # noqa: E402


def _motion_suite(runs=3, jobs=2):
    return og.Suite("tiny").motion_planner(PyRrt, "step = 0.2").runs(runs).seed(7).jobs(jobs)


def test_python_rrt_next_to_rust_planners(tmp_path):
    suite = _motion_suite()
    assert "PyRrt" in suite.planner_names and "planar post" in suite.scene_names
    results = suite.run()
    d = results.to_dict()
    runs = d["motion"]["runs"]
    mine = [r for r in runs if r["planner"] == "PyRrt"]
    rust = [r for r in runs if r["planner"] != "PyRrt"]
    assert len(mine) == 3 and len(rust) == 2 * 3
    for r in mine:
        assert r["status"] == "solved", r.get("message")
        # Graded by the same validators as the Rust planners.
        assert r["processed"]["validity"]["discrete"] and r["processed"]["validity"]["strict"]
        assert r["processed"]["metrics"]["length"] > 0
        assert r["planning_checks"] > 0
    # Same seeds per run as the Rust planners.
    assert sorted({r["seed"] for r in mine}) == sorted({r["seed"] for r in rust})
    assert "PyRrt" in results.report("markdown")


def test_python_results_file_validates_and_submits_like_a_rust_one(tmp_path):
    py_results = _motion_suite(runs=2).retain_planners(["PyRrt"]).run()
    rust_results = og.Suite("tiny").runs(2).seed(7).retain_planners(["RRT-Connect"]).run()
    db = tmp_path / "highscore.sqlite"
    for label, res in [("python", py_results), ("rust", rust_results)]:
        path = tmp_path / f"{label}.json"
        res.save(str(path))
        # Loads and validates exactly like a Rust one, as a dict and as Results.
        loaded = og.load_results(str(path))
        assert loaded == json.loads(path.read_text())
        og.Results.load(str(path)).validate()
        sid = og.submit(str(db), str(path), f"{label}-entrant", team="lab")
        assert sid > 0
    ranking = og.ranking(str(db), "motion/planar-post")
    entries = ranking[0]["entries"]
    assert {e["submitter"] for e in entries} == {"python-entrant", "rust-entrant"}
    assert {e["planner"] for e in entries} == {"PyRrt", "RRT-Connect"}


def test_broken_results_raise_results_error(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"schema_version": 1}')
    with pytest.raises(og.ResultsError):
        og.load_results(str(bad))
    with pytest.raises(ValueError):
        og.Results.from_json("not json")


def test_python_grasp_planner_graded_by_the_shared_evaluator():
    results = (
        og.Suite().grasp_planner(RandomShooting(8), "n = 8")
        .hands(["barrett"]).objects(["salt_can"]).seed(1).physics_per_cell(0).run()
    )
    d = results.to_dict()
    cells = d["grasp"]["cells"]
    assert len(cells) == 1
    cell = cells[0]
    assert cell["planner"] == "RandomShooting" and cell["hand"] == "barrett" and cell["object"] == "salt_can"
    assert cell["generated"] == 8 and cell["evaluated"] == 8
    results.validate()
    assert "RandomShooting" in results.report()


def test_grasp_suite_runs_python_and_rust_planners_in_parallel():
    results = (
        og.Suite().with_reference_grasp("tiny").grasp_planner(RandomShooting(4))
        .jobs(2).seed(3).run()
    )
    planners = {c["planner"] for c in results.to_dict()["grasp"]["cells"]}
    assert "RandomShooting" in planners and len(planners) == 3


def test_planner_errors_become_exceptions_or_failed_runs():
    class Broken(og.GraspPlanner):
        def plan(self, request):
            raise RuntimeError("boom from python")

    with pytest.raises(og.OpenGraspError, match="boom from python"):
        og.Suite().grasp_planner(Broken()).hands(["barrett"]).objects(["salt_can"]).run()

    class BadPath(og.MotionPlanner):
        def plan(self, problem):
            return np.zeros((3, 5))  # wrong dimension

    class Raises(og.MotionPlanner):
        def plan(self, problem):
            raise KeyError("nope")

    class GivesUp(og.MotionPlanner):
        def plan(self, problem):
            return None

    res = (
        og.Suite().motion_planner(BadPath).motion_planner(Raises).motion_planner(GivesUp)
        .motion_scene("planar post").runs(1).run().to_dict()
    )
    by = {r["planner"]: r for r in res["motion"]["runs"]}
    assert "columns" in by["BadPath"]["message"]
    assert "KeyError" in by["Raises"]["message"] and "nope" in by["Raises"]["message"]
    assert by["GivesUp"]["status"] == "timeout"


def test_problem_is_only_valid_during_plan():
    kept = []

    class Keeper(og.MotionPlanner):
        def setup(self, problem):
            assert problem.dim == 2 and problem.active

        def plan(self, problem):
            kept.append(problem)
            assert problem.active and problem.is_valid(problem.start)
            qs = np.array([problem.start, problem.goal["configuration"]])
            assert problem.is_valid_batch(qs).tolist() == [True, True]
            assert problem.satisfies_goal(problem.goal["configuration"])
            assert problem.time_left() > 0 and problem.robot.dof == 2
            return None

    og.Suite().motion_planner(Keeper).motion_scene("planar post").runs(1).jobs(1).run()
    assert kept and not kept[0].active
    with pytest.raises(og.OpenGraspError, match="no longer valid"):
        kept[0].is_valid([0.0, 0.0])
