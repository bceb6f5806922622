import pytest
import quiver


def test_nodes_edges_and_attributes(world):
    g = world
    assert g.node_count == 4
    robot = g.node("robot")
    kitchen = g.find_node("kitchen")
    assert g.type_of(robot) == "robot"
    assert g.name_of(kitchen) == "kitchen"
    assert g.get(robot, "battery") == 0.75
    assert g.get("robot", "battery") == 0.75
    assert g.has_edge(robot, kitchen, "in")
    assert g.has_edge("robot", "kitchen", "in")
    assert not g.has_edge(kitchen, robot, "in")
    assert sorted(g.name_of(n) for n in g.nodes("room")) == ["hallway", "kitchen"]
    (e,) = g.edges_from(robot)
    assert (e.source, e.target, e.type) == (robot, kitchen, "in")
    assert g.edges_to(kitchen, "in") == [e]
    assert g.find_node("nobody") is None
    assert g.edge_count == 2


def test_missing_things_raise_not_found(world):
    with pytest.raises(quiver.NotFoundError, match="no node named 'nobody'"):
        world.node("nobody")
    with pytest.raises(KeyError):
        world.get("robot", "colour")
    assert world.get("robot", "colour", None) is None
    assert world.get("robot", "colour", default=3) == 3


def test_delete_node_removes_its_edges(world):
    with world.transaction() as t:
        t.delete_node("kitchen")
    assert world.find_node("kitchen") is None
    assert world.edges_from(world.node("robot")) == []
    assert world.edge_count == 0
    assert world.check_invariants() == []


def test_names_are_unique_and_self_loops_are_unary_predicates(world):
    t = world.transaction()
    with pytest.raises(ValueError, match="robot"):
        t.create_node("robot", "robot")
    r = world.node("robot")
    with pytest.raises(quiver.Error):
        t.insert_edge(r, r, "RT")
    assert len(t) == 0
    t.abort()
    with world.transaction() as t:
        t.insert_edge(r, r, "moving")
    assert [e.type for e in world.edges_from(r)].count("moving") == 1
    assert [e.type for e in world.edges_to(r)].count("moving") == 1


def test_edge_attributes(world):
    with world.transaction() as t:
        t.set_edge_attr("robot", "kitchen", "in", "since", 12)
    assert world.edge_get(("robot", "kitchen", "in"), "since") == 12
    assert world.edge_attrs(("robot", "kitchen", "in")) == {"since": 12}


def test_two_standalone_replicas_merge_to_the_same_state(world):
    other = quiver.Graph("other")
    other.merge(world.state())
    assert other.node_count == 4
    with other.transaction() as t:
        t.set("robot", "battery", 0.5)
    world.merge(other.state())
    assert world.get("robot", "battery") == 0.5
    assert world.digest() == other.digest()


def test_version_is_the_projects():
    import pathlib
    import re
    top = pathlib.Path(__file__).resolve().parents[2] / "CMakeLists.txt"
    version = re.search(r"project\(quiver VERSION ([0-9.]+)", top.read_text()).group(1)
    assert quiver.__version__ == version


def test_find_name_gives_none_for_an_absent_node(world):
    hall = world.find_node("hallway")
    assert world.find_name(hall) == "hallway"
    with world.transaction() as t:
        t.delete_node(hall)
    assert world.find_name(hall) is None and world.name_of(hall) == ""
