"""Grasp quality and the grasp evaluator from Python."""

import numpy as np
import pytest

import opengrasp as og


def test_four_contacts_on_a_sphere_are_force_closure():
    # A regular tetrahedron of contacts on the unit sphere, normals pointing inwards.
    p = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float) / np.sqrt(3)
    q = og.grasp_quality(p, -p, center_of_mass=[0, 0, 0], max_radius=1.0, friction=0.5)
    assert q["force_closure"] and q["epsilon"] > 0
    # The hull's volume and facet count are opt-in; epsilon is the same either way.
    assert "volume" not in q and "hull_facets" not in q
    full = og.grasp_quality(p, -p, center_of_mass=[0, 0, 0], max_radius=1.0, friction=0.5, hull_statistics=True)
    assert full["volume"] > 0 and full["hull_facets"] > 0 and full["epsilon"] == q["epsilon"]
    assert q["wrench_dimension"] == 6
    # Without friction, point contacts on a sphere cannot resist torques.
    q0 = og.grasp_quality(p, -p, friction=0.0)
    assert not q0["force_closure"] and q0["epsilon"] == 0


def test_two_opposite_contacts_are_not_force_closure_without_torsion():
    p = np.array([[1.0, 0, 0], [-1.0, 0, 0]])
    q = og.grasp_quality(p, -p, friction=0.5)
    assert not q["force_closure"]
    soft = og.grasp_quality(p, -p, friction=0.5, torsional_friction=0.01)
    assert soft["force_closure"]


def test_quality_errors():
    with pytest.raises(og.InvalidInputError):
        og.grasp_quality(np.zeros((2, 3)), np.zeros((2, 3)))
    with pytest.raises(og.InvalidInputError, match="rows"):
        og.grasp_quality(np.zeros((2, 3)), np.ones((3, 3)))


def test_stock_hands_objects_and_evaluator():
    assert "barrett" in og.hand_names() and "salt_can" in og.object_names()
    hand = og.Hand("barrett")
    obj = og.ObjectModel("salt_can")
    assert obj.vertices.shape[1] == 3 and obj.triangles.shape[1] == 3
    info = hand.info
    assert info.name == "barrett" and abs(np.linalg.norm(info.approach) - 1) < 1e-12
    ev = og.GraspEvaluator(hand, obj)
    # Palm 25 cm away on -x, approaching along +x with the closing axis vertical... or not:
    # whatever it gives, the evaluation is deterministic and self-consistent.
    c = obj.center_of_mass
    pose = og.palm_pose(info, c - [0.25, 0, 0], [1.0, 0, 0], [0, 1.0, 0])
    a = ev.evaluate(pose)
    b = ev.evaluate(pose)
    assert a == b
    assert a["status"] == "Closed"
    assert a["contacts"] and a["quality"] is not None
    assert a["force_closure"] == a["quality"]["force_closure"]
    with pytest.raises(og.InvalidInputError):
        og.Hand("no-such-hand")
