import pytest
import quiver


def test_commit_applies_everything_at_once(world):
    t = world.transaction()
    n = t.create_node("mug", "mug", {"full": True})
    t.insert_edge(n, world.node("kitchen"), "in")
    assert world.find_node("mug") is None  # nothing visible before commit
    info = t.commit()
    assert info.ops == 2
    assert world.get("mug", "full") is True
    assert world.has_edge("mug", "kitchen", "in")


def test_abort_discards(world):
    t = world.transaction()
    t.set("robot", "battery", 0.1)
    t.abort()
    assert len(t) == 0
    t.commit()
    assert world.get("robot", "battery") == 0.75


def test_exception_in_with_block_aborts(world):
    with pytest.raises(RuntimeError):
        with world.transaction() as t:
            t.set("robot", "battery", 0.1)
            raise RuntimeError("boom")
    assert world.get("robot", "battery") == 0.75


def test_invalid_call_records_nothing_and_raises(world):
    t = world.transaction()
    t.set("robot", "battery", 0.2)
    with pytest.raises(quiver.Error):
        t.set(quiver.Graph("x").transaction().create_node("a", "b"), "v", 1)  # a node this graph does not have
    assert len(t) == 1
    t.commit()
    assert world.get("robot", "battery") == 0.2


def test_stale_transaction_is_refused_at_commit(world):
    t1 = world.transaction()
    t1.set("kitchen", "lit", True)
    with world.transaction() as t2:
        t2.delete_node("kitchen")
    with pytest.raises(quiver.Error):
        t1.commit()
    assert world.find_node("kitchen") is None


def test_remove_attr_says_whether_the_node_had_it(world):
    with world.transaction() as t:
        assert t.remove_attr("robot", "battery") is True
        assert t.remove_attr("robot", "battery") is False  # gone, as this transaction sees it
        assert t.remove_attr("robot", "never_set") is False
        n = t.create_node("mug", "mug", {"full": True})
        assert t.remove_attr(n, "full") is True
    assert "battery" not in world.attrs("robot")


def test_remove_edge_attr_says_whether_the_edge_had_it(world):
    with world.transaction() as t:
        t.set_edge_attr("robot", "kitchen", "in", "certainty", 0.5)
        assert t.remove_edge_attr("robot", "kitchen", "in", "certainty") is True  # set in this transaction
        assert t.remove_edge_attr("robot", "kitchen", "in", "certainty") is False
        assert t.remove_edge_attr("robot", "kitchen", "in", "never_set") is False
    with world.transaction() as t:
        t.set_edge_attr("robot", "kitchen", "in", "since", 3)
    with world.transaction() as t:
        assert t.remove_edge_attr("robot", "kitchen", "in", "since") is True  # the replica's
