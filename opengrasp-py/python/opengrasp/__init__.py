"""OpenGRASP-rs from Python.

The SDK with numpy arrays (robots, kinematics, scenes, validity, grasp quality, the grasp
evaluator) and the standard benchmark suite, into which Python grasp and motion planners are
entered next to the Rust reference planners and graded by the same code::

    import opengrasp as og

    class MyPlanner(og.MotionPlanner):
        def plan(self, problem):
            ...  # return a (K, dim) array from problem.start to the goal

    results = og.Suite().motion_planner(MyPlanner).motion_scene("planar post").runs(5).run()
    results.save("results.json")
"""

from ._opengrasp import (
    GraspCandidate,
    GraspEvaluator,
    GraspRequest,
    Hand,
    HandInfo,
    ObjectModel,
    Problem,
    ProblemSet,
    Results,
    Robot,
    Scene,
    Suite,
    __version__,
    grasp_quality,
    hand_names,
    kitchen,
    load_problem_sets,
    load_results,
    object_names,
    palm_pose,
    ranking,
    register_benchmark,
    scene_names,
    submit,
)
from .errors import (
    HighscoreError,
    InvalidInputError,
    ModelError,
    OpenGraspError,
    PlanningError,
    ResultsError,
)


class GraspPlanner:
    """Base class of Python grasp planners (duck typing works too: any object with ``plan``).

    ``plan(request)`` gets a :class:`GraspRequest` (hand info, the object's ``vertices`` and
    ``triangles`` as numpy arrays, a ``seed``) and returns a list of :class:`GraspCandidate`.
    The planner never scores its candidates: the suite's evaluator does. ``name`` (default:
    the class name) identifies it in results. Planners are shared between jobs, so ``plan``
    should not depend on state changed by earlier calls.
    """

    @property
    def name(self) -> str:
        return type(self).__name__

    def plan(self, request: GraspRequest) -> list:
        raise NotImplementedError("GraspPlanner subclasses implement plan(request)")


class MotionPlanner:
    """Base class of Python motion planners (duck typing works too: any object with ``plan``).

    The suite makes one instance per job from the class (or any factory) it was given.
    ``setup(problem)`` (optional) prepares for queries in a scene (no start or goal yet);
    ``plan(problem)`` gets a :class:`Problem` (``start``, ``goal``, ``limits``, ``is_valid``,
    ``is_valid_batch``, ``motion_valid``, ``time_left()``, ``seed``, ``step``) and returns the
    path as a ``(K, dim)`` array from the start to a goal configuration (or a dict
    ``{"path": ..., "iterations": n}``), or ``None`` if it found no path in time. The
    problem object is only valid during the call.
    """

    @property
    def name(self) -> str:
        return type(self).__name__

    def setup(self, problem: Problem) -> None:
        pass

    def plan(self, problem: Problem):
        raise NotImplementedError("MotionPlanner subclasses implement plan(problem)")


__all__ = [
    "GraspCandidate",
    "GraspEvaluator",
    "GraspPlanner",
    "GraspRequest",
    "Hand",
    "HandInfo",
    "HighscoreError",
    "InvalidInputError",
    "ModelError",
    "MotionPlanner",
    "ObjectModel",
    "OpenGraspError",
    "PlanningError",
    "Problem",
    "ProblemSet",
    "Results",
    "ResultsError",
    "Robot",
    "Scene",
    "Suite",
    "__version__",
    "grasp_quality",
    "hand_names",
    "kitchen",
    "load_problem_sets",
    "load_results",
    "object_names",
    "palm_pose",
    "ranking",
    "register_benchmark",
    "scene_names",
    "submit",
]
