import math

import numpy as np
import pytest
import quiver


def rot_z(theta):
    return [math.cos(theta / 2), 0.0, 0.0, math.sin(theta / 2)]


def test_rt_edges_and_lookups(world):
    with world.transaction() as t:
        arm = t.create_node("arm", "arm")
        t.set_rt("world", "robot", translation=[1, 0, 0], rotation=rot_z(math.pi / 2), stamp=10)
        t.set_rt("robot", arm, translation=[0, 2, 0.5], stamp=10)
    parent, X_WR, stamp = world.rt_edge("robot")
    assert parent == world.node("world") and stamp == 10
    assert X_WR.shape == (4, 4)
    np.testing.assert_allclose(X_WR[:3, 3], [1, 0, 0])
    np.testing.assert_allclose(X_WR[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-12)
    assert world.rt_children("robot") == [arm]
    assert world.rt_roots() == [world.node("world")]

    frames = quiver.FrameTree(world)
    X_WA = frames.lookup("world", "arm")
    # X_WA = X_WR * X_RA: the arm's (0, 2, 0.5) in the robot frame, rotated 90 degrees about z.
    np.testing.assert_allclose(X_WA[:3, 3], [1 - 2, 0, 0.5], atol=1e-12)
    np.testing.assert_allclose(frames.lookup("arm", "world") @ X_WA, np.eye(4), atol=1e-12)
    np.testing.assert_allclose(frames.transform_point("world", "arm", [1, 0, 0]), [-1, 1, 0.5], atol=1e-12)

    # The tree follows later commits; a reader sees them too.
    reader = frames.reader()
    with world.transaction() as t:
        t.set_rt("world", "robot", np.eye(4), stamp=20)
    np.testing.assert_allclose(reader.lookup("world", "arm")[:3, 3], [1 - 1, 2, 0.5], atol=1e-12)
    # Interpolated half-way between the two samples of world -> robot.
    X = frames.lookup_at("world", "robot", 15)
    np.testing.assert_allclose(X[:3, 3], [0.5, 0, 0], atol=1e-9)


def test_lookup_errors(world):
    frames = quiver.FrameTree(world)
    with pytest.raises(quiver.NotFoundError):
        frames.lookup("world", "nowhere")
    with pytest.raises(quiver.Error) as e:
        frames.lookup("world", "kitchen")  # separate trees
    assert e.value.code == "not_connected"


def test_cycles_and_bad_matrices_are_refused(world):
    with world.transaction() as t:
        t.set_rt("world", "robot", np.eye(4))
    t = world.transaction()
    with pytest.raises(quiver.Error, match="cycle"):
        t.set_rt("robot", "world", np.eye(4))
    with pytest.raises(ValueError, match="rigid transform"):
        t.set_rt("world", "kitchen", np.ones((4, 4)))
    assert len(t) == 0
