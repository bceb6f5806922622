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


def test_a_deletion_carries_what_was_deleted(world):
    with world.transaction() as t:
        cup = t.create_node("cup", "cup", {"full": True, "colour": "blue"})
        t.insert_edge(cup, "robot", "near", {"distance": 0.5})
    seen = []
    world.subscribe(seen.append)
    with world.transaction() as t:
        t.delete_node(cup)
    gone = [c for c in seen[0].nodes if c.kind == "deleted"]
    assert len(gone) == 1 and gone[0].name == "cup" and gone[0].type == "cup"
    assert gone[0].values == {"full": True, "colour": "blue"}
    edges = [e for e in seen[0].edges if e.kind == "deleted"]
    assert len(edges) == 1 and edges[0].values == {"distance": 0.5}


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


def test_a_filtered_subscription_sees_only_its_part(world):
    mugs, battery = [], []
    world.subscribe(mugs.append, node_types=["mug"])
    world.subscribe(battery.append, attributes=["battery"])
    with world.transaction() as t:
        t.set("robot", "battery", 0.5)
    assert mugs == [] and len(battery) == 1
    with world.transaction() as t:
        t.create_node("mug", "mug")
        t.create_node("room", "attic")
    assert len(mugs) == 1 and [c.type for c in mugs[0].nodes] == ["mug"]
    assert len(battery) == 1


def test_a_batch_names_its_origin(world):
    seen = []
    world.subscribe(seen.append)
    with world.transaction() as t:
        t.set("robot", "battery", 0.5)
    # A standalone graph has no replicator to name agents: the origin's id as text.
    assert seen[0].origin_name == str(world.replica)
