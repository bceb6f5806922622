import pytest
import quiver


def test_subscribers_see_each_commit(world):
    seen = []
    sid = world.subscribe(lambda b: seen.append(b))
    with world.transaction() as t:
        n = t.create_node("mug", "mug", {"full": True})
        t.set("robot", "battery", 0.5)
    assert len(seen) == 1
    b = seen[0]
    assert b.local and b.origin == world.replica
    kinds = {(c.kind, c.type) for c in b.nodes}
    assert ("created", "mug") in kinds and ("updated", "robot") in kinds
    robot_change = next(c for c in b.nodes if c.type == "robot")
    assert robot_change.attrs == ["battery"]
    assert any(c.id == n and c.attrs == ["full"] for c in b.nodes)
    world.unsubscribe(sid)
    with world.transaction() as t:
        t.set("robot", "battery", 0.4)
    assert len(seen) == 1


def test_edge_events_and_remote_origin(world):
    other = quiver.Graph("other")
    batches = []
    other.subscribe(batches.append)
    other.merge(world.state())
    assert len(batches) == 1 and not batches[0].local
    assert batches[0].origin != other.replica
    assert {e.key.type for e in batches[0].edges} == {"in", "transitable"}


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_a_raising_callback_does_not_break_the_commit(world):
    def bad(_):
        raise ValueError("subscriber bug")
    world.subscribe(bad)
    with world.transaction() as t:
        t.set("robot", "battery", 0.3)
    assert world.get("robot", "battery") == 0.3
