"""Exceptions raised by OpenGRASP-rs; each carries the Rust error's message.

``InvalidInputError``, ``ModelError`` and ``ResultsError`` are also ``ValueError``\\ s, so
``except ValueError`` catches bad input as usual.
"""


class OpenGraspError(Exception):
    """Base class of every error raised by the ``opengrasp`` package."""


class InvalidInputError(OpenGraspError, ValueError):
    """Bad arguments: wrong dimensions, non-finite values, joint limits, unknown names."""


class ModelError(OpenGraspError, ValueError):
    """A malformed robot, mesh, hand or object file (URDF, SRDF, STL/OBJ/DAE, JSON spec)."""


class ResultsError(OpenGraspError, ValueError):
    """A results file that does not parse or does not validate."""


class PlanningError(OpenGraspError):
    """A planner or solver failed (time-outs, hull or QP failures, a Python planner's error)."""


class HighscoreError(OpenGraspError):
    """The high-score store failed (database errors)."""


__all__ = [
    "OpenGraspError",
    "InvalidInputError",
    "ModelError",
    "ResultsError",
    "PlanningError",
    "HighscoreError",
]
