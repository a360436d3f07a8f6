"""The SDK from Python: robots, kinematics, validity, errors."""

import numpy as np
import pytest

import opengrasp as og


def test_planar_fk_matches_closed_form(planar):
    for q in [(0.0, 0.0), (0.3, -0.7), (1.2, 0.3), (-2.0, 1.5)]:
        pose = planar.fk(np.array(q))
        x = 0.5 * np.cos(q[0]) + 0.4 * np.cos(q[0] + q[1])
        y = 0.5 * np.sin(q[0]) + 0.4 * np.sin(q[0] + q[1])
        assert pose.shape == (4, 4)
        assert abs(pose[0, 3] - x) < 1e-12 and abs(pose[1, 3] - y) < 1e-12
        yaw = np.arctan2(pose[1, 0], pose[0, 0])
        assert abs(np.angle(np.exp(1j * (yaw - q[0] - q[1])))) < 1e-12


def test_fk_accepts_lists_and_batches(planar, rng):
    qs = rng.uniform(-1, 1, size=(50, 2))
    batch = planar.fk_batch(qs)
    assert batch.shape == (50, 4, 4)
    for q, pose in zip(qs, batch):
        np.testing.assert_allclose(pose, planar.fk(list(q)), atol=1e-14)
    assert planar.fk_all([0.1, 0.2]).shape == (len(planar.link_names), 4, 4)


def test_jacobian_matches_finite_differences(planar):
    q = np.array([0.4, -0.9])
    jac = planar.jacobian(q)
    assert jac.shape == (6, 2)
    h = 1e-6
    for i in range(2):
        dq = np.zeros(2)
        dq[i] = h
        dp = (planar.fk(q + dq)[:3, 3] - planar.fk(q - dq)[:3, 3]) / (2 * h)
        np.testing.assert_allclose(jac[:3, i], dp, atol=1e-8)
    np.testing.assert_allclose(jac[5], [1.0, 1.0], atol=1e-12)


def test_ik_reaches_fk_target():
    arm = og.Robot.seven_dof_arm()
    q_true = arm.home() + 0.3
    target = arm.fk(q_true, link="tool")
    sol = arm.ik(target, link="tool", group="arm", seed=3)
    assert sol["converged"] and sol["status"] == "converged"
    assert sol["position_error"] < 1e-6
    np.testing.assert_allclose(arm.fk(sol["q"], link="tool"), target, atol=1e-5)


def test_robot_from_urdf_string_and_srdf():
    urdf = """<robot name="pendulum">
      <link name="base"/>
      <link name="bob"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
      <joint name="swing" type="revolute">
        <parent link="base"/><child link="bob"/>
        <origin xyz="0 0 1"/><axis xyz="0 1 0"/>
        <limit lower="-1.5" upper="1.5" effort="10" velocity="2"/>
      </joint>
    </robot>"""
    srdf = """<robot name="pendulum"><group name="swinger"><joint name="swing"/></group></robot>"""
    r = og.Robot.from_urdf_string(urdf, srdf)
    assert r.dof == 1 and r.joint_names == ["swing"]
    np.testing.assert_allclose(r.limits, [[-1.5, 1.5]])
    assert ("swinger", ["swing"]) in r.groups
    np.testing.assert_allclose(r.fk([0.0], link="bob")[:3, 3], [0, 0, 1], atol=1e-12)


def test_errors_are_exceptions_with_rust_messages(planar):
    with pytest.raises(og.InvalidInputError, match="expected 2 values"):
        planar.fk([0.0, 0.0, 0.0])
    with pytest.raises(ValueError):  # InvalidInputError is a ValueError
        planar.fk([np.nan, 0.0])
    with pytest.raises(og.OpenGraspError, match="unknown"):
        planar.fk([0.0, 0.0], link="no_such_link")
    with pytest.raises(og.ModelError):
        og.Robot.from_urdf_string("<robot name='x'><link name='a'/><joint name='j' type='revolute'/></robot>")
    with pytest.raises(og.OpenGraspError):
        og.Robot.from_urdf("/nonexistent/robot.urdf")
    scaled = np.eye(4)
    scaled[:3, :3] *= 2
    with pytest.raises(og.InvalidInputError, match="not a rotation"):
        planar.ik(scaled)
    with pytest.raises(og.InvalidInputError, match="last row"):
        planar.ik(np.eye(4) * 2)
    with pytest.raises(og.InvalidInputError, match="unknown scene"):
        og.Scene("no such scene")


def test_scene_validity_single_batched_and_motion(rng):
    scene = og.Scene("planar post")
    assert scene.dim == 2 and scene.joint_names
    assert scene.is_valid(scene.start)
    qs = rng.uniform(scene.limits[:, 0], scene.limits[:, 1], size=(2000, 2))
    batch = scene.is_valid_batch(qs)
    assert batch.dtype == np.bool_ and batch.shape == (2000,)
    single = np.array([scene.is_valid(q) for q in qs])
    np.testing.assert_array_equal(batch, single)
    assert 0 < batch.sum() < len(qs)  # the post blocks part of the space
    # Fortran-ordered and float32 input give the same answer.
    np.testing.assert_array_equal(scene.is_valid_batch(np.asfortranarray(qs)), batch)
    # The straight segment start -> goal sweeps the arm through the post.
    goal = scene.goal["configuration"]
    assert scene.goal["kind"] == "configuration"
    assert not scene.motion_valid(scene.start, goal)
    assert scene.motion_valid(scene.start, scene.start + 0.01)
    c = scene.clearance(scene.start)
    assert c is not None and c > 0
    cb = scene.clearance_batch(qs[:10])
    np.testing.assert_allclose(cb, [scene.clearance(q) for q in qs[:10]])
    v = scene.validate_path(np.array([scene.start, goal]))
    assert v == {"discrete": False, "strict": False, "continuous": False}
    with pytest.raises(og.InvalidInputError, match="expected 2 columns"):
        scene.is_valid_batch(np.zeros((3, 5)))


def test_standard_scene_batched_equals_single(rng):
    scene = og.Scene("standard (7-DoF stand-in)")
    assert scene.dim == 7 and scene.tip == "tool"
    qs = rng.uniform(scene.limits[:, 0], scene.limits[:, 1], size=(300, 7))
    np.testing.assert_array_equal(scene.is_valid_batch(qs), [scene.is_valid(q) for q in qs])
    m = scene.path_metrics(np.array([scene.start, scene.start + 0.05]))
    assert m["waypoints"] == 2 and m["length"] == pytest.approx(0.05 * np.sqrt(7))
