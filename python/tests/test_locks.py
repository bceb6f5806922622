import pytest
import quiver


def test_a_lock_refuses_other_replicas_writes_into_its_scope(world):
    mine = quiver.LockManager(world)
    mine.install()
    mine.acquire("robot", 5)
    mine.tick()
    assert mine.holds("robot")
    assert mine.winner("robot").priority == 5

    other = quiver.Graph("other")
    theirs = quiver.LockManager(other)
    theirs.install()
    other.merge(world.state())
    assert theirs.locked_by_other(other.node("robot"))
    t = other.transaction()
    t.set("robot", "battery", 0.1)
    with pytest.raises(quiver.RefusedError):
        t.commit()
    with pytest.raises(quiver.RefusedError):
        theirs.acquire("robot", 3)  # a lower priority waits for the lease
    # Outside the scope writes go through.
    with other.transaction() as t:
        t.set("kitchen", "lit", True)
    # Released: the other replica may write again.
    mine.release("robot")
    other.merge(world.state())
    assert not theirs.locked_by_other(other.node("robot"))
    with other.transaction() as t:
        t.set("robot", "battery", 0.1)
