"""quiver.dsr, pydsr's names over Quiver: the call sequences a public pydsr agent makes.

The sequence below is the one RoboComp's social-navigation agent `human_social_spaces_dsr`
(DSRGraph(0, "human_social_spaces_dsr", 121)) makes, written here from its public description:
it connects the six signals, creates a person node with a person_id attribute and places it under
"world" with rt_api.insert_or_assign_edge_RT, reads people back by type (attrs[...].value,
rt_api.get_edge_RT), creates a personal_space node with list attributes and a "has" edge from the
person, walks node.edges, updates the space's attributes and writes the node back
(update_node), and reads RT edges with get_edges_to_id. A second agent (another process's
DSRGraph on the same domain) watches through signals and deletes what the first made. Two
quiver.Agent replicas over Cyclone DDS, loopback only.
"""

import math

import pytest

import quiver
from quiver.dsr import DSRGraph, Edge, Node, Attribute, signals, rt_api
from conftest import wait

DOMAIN = 88


@pytest.fixture
def pair(tmp_path):
    world = tmp_path / "world.json"
    world.write_text('{"quiver_world": 1, "nodes": [{"name": "root", "type": "root"}, '
                     '{"name": "world", "type": "world"}]}')
    g1 = DSRGraph(0, "human_social_spaces_dsr", 121, str(world), domain=DOMAIN, join_wait=0.5)
    g2 = DSRGraph(0, "social_observer", 122, str(world), domain=DOMAIN)
    yield g1, g2
    g2.close()
    g1.close()


def test_a_pydsr_agents_call_sequence_runs_with_its_import_changed(pair):
    g1, g2 = pair
    seen = []
    signals.connect(g2, signals.UPDATE_NODE, lambda id, type: seen.append(("node", id, type)))
    signals.connect(g2, signals.UPDATE_NODE_ATTR, lambda id, names: seen.append(("attrs", id, tuple(names))))
    signals.connect(g2, signals.UPDATE_EDGE, lambda fr, to, type: seen.append(("edge", fr, to, type)))
    signals.connect(g2, signals.UPDATE_EDGE_ATTR, lambda fr, to, type, names: seen.append(("edge_attrs", fr, to, type)))
    signals.connect(g1, signals.DELETE_NODE, lambda id: seen.append(("deleted", id)))
    signals.connect(g1, signals.DELETE_EDGE, lambda fr, to, type: seen.append(("deleted_edge", fr, to, type)))
    signals.connect(g1, signals.DELETE_NODE_OBJ, lambda node: seen.append(("deleted_obj", node.name, node.type)))
    assert g1.get_agent_id() == 121 and g1.get_agent_name() == "human_social_spaces_dsr"
    assert g1.get_node_root().name == "root"

    # HumanToDSRPub_newPeopleData: a person node, placed under "world".
    new_node = Node(agent_id=121, type="person", name="person_7")
    new_node.attrs["person_id"] = Attribute(7, 121)
    person_id = g1.insert_node(new_node)
    assert isinstance(person_id, int) and new_node.id == person_id
    assert g1.insert_node(Node(121, "person", "person_7")) is None, "a taken name is refused, as pydsr"
    rt = rt_api(g1)
    assert rt.insert_or_assign_edge_RT(g1.get_node("world"), person_id, [1000.0, 2000.0, 0.0], [0.0, 0.5, 0.0])

    # get_people_from_dsr
    people = g1.get_nodes_by_type("person")
    assert [p.attrs["person_id"].value for p in people] == [7]
    edge_rt = rt.get_edge_RT(g1.get_node("world"), people[0].id)
    tx, ty, tz = edge_rt.attrs["rt_translation"].value
    rx, ry, rz = edge_rt.attrs["rt_rotation_euler_xyz"].value
    assert (round(tx), round(ty), round(tz)) == (1000, 2000, 0)
    assert math.isclose(ry, 0.5, abs_tol=1e-6) and abs(rx) < 1e-6 and abs(rz) < 1e-6

    # update_personal_spaces: the space node, its "has" edge from the person.
    space = Node(agent_id=121, type="personal_space", name="personal_space_7")
    space.attrs["ps_social_x_pos"] = Attribute([1.0, 2.0, 3.0], 121)
    space.attrs["ps_social_y_pos"] = Attribute([4.0, 5.0, 6.0], 121)
    space_id = g1.insert_node(space)
    assert g1.insert_or_assign_edge(Edge(space_id, person_id, "has", 121))
    person_node = g1.get_node(person_id)
    found = None
    for destination, type_edge in person_node.edges:
        if type_edge == "has" and g1.get_node(destination).type == "personal_space":
            found = g1.get_node(destination)
    assert found is not None and found.id == space_id
    found.attrs["ps_social_x_pos"].value = [7.0, 8.0]
    assert g1.update_node(found)
    assert g1.get_node(space_id).attrs["ps_social_x_pos"].value == pytest.approx([7.0, 8.0])

    # get_interactive_objects_from_drs: RT edges into a node carry DSR's RT attributes.
    into = g1.get_edges_to_id(person_id)
    assert [e.type for e in into] == ["RT"]
    assert [round(v) for v in into[0].attrs["rt_translation"].value] == [1000, 2000, 0]

    # The other agent sees it all, under the same ids, through its signals.
    assert wait(lambda: g2.get_node("personal_space_7") is not None and
                g2.get_node("personal_space_7").attrs["ps_social_x_pos"].value == pytest.approx([7.0, 8.0]))
    assert g2.get_id_from_name("person_7") == person_id and g2.get_name_from_id(space_id) == "personal_space_7"
    assert g2.get_edge("person_7", "personal_space_7", "has").destination == space_id
    assert g2.get_edge(person_id, space_id, "has").origin == person_id
    assert wait(lambda: ("node", space_id, "personal_space") in seen and ("edge", person_id, space_id, "has") in seen
                and ("attrs", space_id, ("ps_social_x_pos",)) in seen)

    # It deletes them; the first agent's delete signals carry the ids and the deleted node.
    assert g2.delete_edge(person_id, space_id, "has")
    assert not g2.delete_edge(person_id, space_id, "has"), "already gone"
    assert g2.delete_node("personal_space_7")
    assert wait(lambda: ("deleted", space_id) in seen and ("deleted_edge", person_id, space_id, "has") in seen
                and ("deleted_obj", "personal_space_7", "personal_space") in seen)
    assert g1.get_node(space_id) is None and g1.size() == 3


def test_an_attribute_keeps_its_type_as_pydsr_says(pair):
    g1, _ = pair
    n = Node(121, "person", "p")
    n.attrs["count"] = Attribute(3, 121)
    g1.insert_node(n)
    n.attrs["count"].value = 4.5  # pydsr: "Attributes cannot change type" (a TypeError)
    with pytest.raises(TypeError):
        g1.update_node(n)
    n.attrs["count"].value = "four"
    with pytest.raises(TypeError, match="holds a int32; a string would change its type"):
        g1.update_node(n)
    assert g1.get_node("p").attrs["count"].value == 3
    n.attrs["count"].value = 5
    assert g1.update_node(n) and g1.get_node("p").attrs["count"].value == 5


def test_an_rt_edge_written_back_moves_its_child_as_pydsr_does(pair):
    """pydsr's way to move a node: get_edge(parent, child, "RT"), change rt_translation (or
    rt_rotation_euler_xyz), insert_or_assign_edge(). The child's pose moves (set_rt); the edge's
    other attributes stay the RT edge's (kept on the child as rt:<name>)."""
    g1, g2 = pair
    world = g1.get_node("world")
    cup = g1.insert_node(Node(121, "cup", "cup"))
    rt = rt_api(g1)
    assert rt.insert_or_assign_edge_RT(world, cup, [100.0, 0.0, 0.0], [0.0, 0.0, 0.3])

    e = g1.get_edge(world.id, cup, "RT")
    assert [round(v) for v in e.attrs["rt_translation"].value] == [100, 0, 0]
    e.attrs["rt_translation"].value = [250.0, -40.0, 10.0]
    e.attrs["rt_covariance"] = Attribute([0.1, 0.2], 121)
    assert g1.insert_or_assign_edge(e)
    assert rt.get_translation(world.id, cup) == pytest.approx([250.0, -40.0, 10.0])
    back = rt.get_edge_RT(world, cup)
    assert back.attrs["rt_rotation_euler_xyz"].value == pytest.approx([0.0, 0.0, 0.3], abs=1e-12)
    assert back.attrs["rt_covariance"].value == pytest.approx([0.1, 0.2])

    def pose_and_attrs(g):
        n = g.find_node("cup")
        parent, X_PC, _ = g.rt_edge(n)
        return parent == g.find_node("world"), X_PC, g.attrs(n)
    same_parent, X_PC, attrs = g1.agent.call(pose_and_attrs)
    assert same_parent and X_PC[:3, 3] == pytest.approx([0.25, -0.04, 0.01])
    assert "rt:rt_translation" not in attrs and "rt:rt_rotation_euler_xyz" not in attrs
    assert attrs["rt:rt_covariance"] == pytest.approx([0.1, 0.2])

    e = g1.get_edge("world", "cup", "RT")
    e.attrs["rt_rotation_euler_xyz"].value = [0.0, 0.5, 0.0]
    assert g1.insert_or_assign_edge(e)
    back = rt.get_edge_RT(world, cup)
    assert back.attrs["rt_rotation_euler_xyz"].value == pytest.approx([0.0, 0.5, 0.0], abs=1e-12)
    assert back.attrs["rt_translation"].value == pytest.approx([250.0, -40.0, 10.0])

    e.attrs["rt_translation"].value = [1.0, 2.0]
    with pytest.raises(ValueError, match="rt_translation must be 3 numbers"):
        g1.insert_or_assign_edge(e)
    assert rt.get_translation(world.id, cup) == pytest.approx([250.0, -40.0, 10.0])

    # The other agent reads the same pose through its own rt_api.
    assert wait(lambda: g2.get_node("cup") is not None and
                rt_api(g2).get_translation(world.id, cup) == pytest.approx([250.0, -40.0, 10.0]))


def test_insert_or_assign_edge_of_a_new_rt_edge_places_or_moves_the_child(pair):
    g1, _ = pair
    world = g1.get_node("world")
    table = g1.insert_node(Node(121, "table", "table"))
    cup = g1.insert_node(Node(121, "cup", "cup"))
    rt = rt_api(g1)

    e = Edge(table, world.id, "RT", 121)
    e.attrs["rt_translation"] = Attribute([1000.0, 0.0, 0.0], 121)
    e.attrs["rt_rotation_euler_xyz"] = Attribute([0.0, 0.0, 0.0], 121)
    assert g1.insert_or_assign_edge(e)
    assert rt.get_translation(world.id, table) == pytest.approx([1000.0, 0.0, 0.0])

    e = Edge(cup, world.id, "RT", 121)
    e.attrs["rt_translation"] = Attribute([0.0, 500.0, 0.0], 121)
    assert g1.insert_or_assign_edge(e)
    e = Edge(cup, table, "RT", 121)  # a new parent: a move
    e.attrs["rt_translation"] = Attribute([0.0, 0.0, 750.0], 121)
    assert g1.insert_or_assign_edge(e)
    assert g1.get_edge(world.id, cup, "RT") is None
    assert [(x.origin, x.type) for x in g1.get_edges_to_id(cup)] == [(table, "RT")]
    assert rt.get_translation(table, cup) == pytest.approx([0.0, 0.0, 750.0])
    assert rt.get_edge_RT(g1.get_node(table), cup).attrs["rt_rotation_euler_xyz"].value == pytest.approx([0.0, 0.0, 0.0])
