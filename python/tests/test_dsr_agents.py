"""quiver.dsr under the graph call sequences of two more public RoboComp pydsr agents (issue 24).

Each test performs, through quiver.dsr, the sequence of graph calls one named agent makes, and
asserts what that agent relies on. The sequences are described here in our own words from
reading the agents' public sources; none of their code is used. Two DSRGraph replicas on one DDS
domain, loopback only: the agent under test and a second agent that plays its peers (the
process that publishes people or camera frames, the one that commands the arm).

Two of them found where the facade differed from pydsr (numpy uint8 frames, UPDATE_NODE on
attribute changes); it now does as pydsr does.
"""

import json
import time

import numpy as np
import pytest

from quiver.dsr import DSRGraph, Edge, Node, Attribute, signals, rt_api
from conftest import wait

DOMAIN = 86


def world_file(tmp_path, nodes):
    path = tmp_path / "world.json"
    path.write_text(json.dumps({"quiver_world": 1, "nodes": [{"name": "root", "type": "root"},
                                                             {"name": "world", "type": "world"}] + nodes}))
    return str(path)


# ---------------------------------------------------------------------------------------------
# robocomp/manipulation_kinova_gen3, agents/gen3_dsr/src/specificworker.py
#
# The agent that puts a Kinova Gen3 arm into the graph. It starts DSRGraph(0, "gen3 DSR", 30) and
# an rt_api. At start it gets the node "hand_camera" by name and gives it the camera's
# description as new attributes, each an Attribute(value, 30): image sizes, channel counts and
# camera ids as ints, focal lengths and the depth factor as floats, and the colour and depth
# frames as uint8 numpy arrays of shape (rows, cols, channels); then update_node(camera). It gets
# "gripper" by name, adds two float attributes (the finger distance and the target finger
# distance, both 0.0), update_node(gripper), and keeps the gripper's id. It connects
# UPDATE_NODE_ATTR and UPDATE_NODE. Every period it gets "arm" by name, places the gripper under
# it with rt_api.insert_or_assign_edge_RT(arm_node, gripper_id, translation in mm, Euler angles;
# both numpy arrays) and calls update_node(arm); it gets "hand_camera" again, sets .value of the
# frame and size attributes it created, and update_node(camera); it can also set .value of the
# gripper's finger distance and update_node(gripper). Its UPDATE_NODE_ATTR slot reacts only to the
# gripper's id: when "target" is among the names it gets the node by id and reads attrs["target"]
# (a pose: x, y, z in mm and three angles) to move the arm; when "gripper_target_finger_distance"
# is among them it reads that float to move the fingers. Another agent writes those two.
# ---------------------------------------------------------------------------------------------

@pytest.fixture
def gen3(tmp_path):
    world = world_file(tmp_path, [{"name": "arm", "type": "kinova_arm"},
                                  {"name": "gripper", "type": "gripper"},
                                  {"name": "hand_camera", "type": "rgbd"}])
    g = DSRGraph(0, "gen3 DSR", 30, world, domain=DOMAIN, join_wait=0.5)
    commander = DSRGraph(0, "arm_commander", 31, world, domain=DOMAIN)
    yield g, commander
    commander.close()
    g.close()


def test_gen3_dsr_call_sequence(gen3):
    g, commander = gen3
    rt = rt_api(g)

    # Start: the camera's description on "hand_camera" (the frames are the next test).
    camera = g.get_node("hand_camera")
    assert camera is not None and camera.attrs == {}
    for name, value in [("cam_rgb_width", 640), ("cam_rgb_height", 480), ("cam_rgb_depth", 3),
                        ("cam_rgb_focalx", 653.68229), ("cam_rgb_focaly", 651.855994), ("cam_rgb_cameraID", 0),
                        ("cam_depth_width", 270), ("cam_depth_height", 480), ("cam_depth_depth", 2),
                        ("cam_depth_focalx", 360.01333), ("cam_depth_focaly", 360.013366699),
                        ("cam_depthFactor", 0.01), ("cam_depth_cameraID", 1)]:
        camera.attrs[name] = Attribute(value, 30)
    assert g.update_node(camera)

    # Start: the gripper's two floats; its id is kept.
    gripper = g.get_node("gripper")
    gripper.attrs["gripper_finger_distance"] = Attribute(float(0.0), 30)
    gripper.attrs["gripper_target_finger_distance"] = Attribute(float(0.0), 30)
    assert g.update_node(gripper)
    gripper_id = gripper.id
    assert isinstance(gripper_id, int) and g.get_id_from_name("gripper") == gripper_id

    # The slots: only the gripper's id, and only the two command attributes, lead to a read.
    targets, finger_goals, gripper_changes = [], [], []

    def on_node_attrs(id, attribute_names):
        if id != gripper_id:
            return
        gripper_changes.append(list(attribute_names))
        if "target" in attribute_names:
            targets.append(list(g.get_node(id).attrs["target"].value))
        if "gripper_target_finger_distance" in attribute_names:
            finger_goals.append(g.get_node(id).attrs["gripper_target_finger_distance"].value)

    signals.connect(g, signals.UPDATE_NODE_ATTR, on_node_attrs)
    signals.connect(g, signals.UPDATE_NODE, lambda id, type: None)  # its slot does nothing

    # A period: the arm's pose puts the gripper under "arm" (mm and radians, as numpy arrays).
    arm = g.get_node("arm")
    translation = np.multiply(np.array([0.35, -0.12, 0.42]), 1000)
    rotation = np.radians(np.array([90.0, 0.0, 45.0]))
    assert rt.insert_or_assign_edge_RT(arm, gripper_id, translation, rotation)
    assert g.update_node(arm), "the arm node, unchanged, is written back"
    edge = rt.get_edge_RT(g.get_node("arm"), gripper_id)
    assert edge is not None and edge.origin == arm.id and edge.destination == gripper_id
    assert edge.attrs["rt_translation"].value == pytest.approx([350.0, -120.0, 420.0])
    assert edge.attrs["rt_rotation_euler_xyz"].value == pytest.approx(list(rotation), abs=1e-9)
    assert [(e.origin, e.type) for e in g.get_edges_to_id(gripper_id)] == [(arm.id, "RT")]

    # The next period: a new pose replaces the old one (one RT edge, the new translation).
    assert rt.insert_or_assign_edge_RT(g.get_node("arm"), gripper_id, np.array([300.0, 0.0, 400.0]),
                                       np.radians(np.array([0.0, 90.0, 0.0])))
    assert rt.get_translation(arm.id, gripper_id) == pytest.approx([300.0, 0.0, 400.0])
    assert len(g.get_edges_to_id(gripper_id)) == 1

    # A period with frames: the size attributes it created are set through .value.
    camera = g.get_node("hand_camera")
    camera.attrs["cam_rgb_height"].value = 720
    camera.attrs["cam_rgb_width"].value = 1280
    camera.attrs["cam_depth_height"].value = 270
    camera.attrs["cam_depth_width"].value = 480
    assert g.update_node(camera)
    back = g.get_node("hand_camera")
    assert (back.attrs["cam_rgb_width"].value, back.attrs["cam_rgb_height"].value) == (1280, 720)
    assert back.attrs["cam_rgb_focalx"].value == pytest.approx(653.68229, rel=1e-6)
    assert back.attrs["cam_depthFactor"].value == pytest.approx(0.01, rel=1e-6)

    # The gripper's state, reported through .value of the float it created.
    gripper = g.get_node("gripper")
    gripper.attrs["gripper_finger_distance"].value = 1 - 0.25
    assert g.update_node(gripper)

    # Its own writes of the gripper reach its slots too (as pydsr's do) but are not commands.
    assert wait(lambda: ["gripper_finger_distance"] in gripper_changes)
    assert targets == [] and finger_goals == []

    # The peer sees all of it under the same ids and names.
    assert wait(lambda: commander.get_node("gripper") is not None and
                "gripper_finger_distance" in commander.get_node("gripper").attrs and
                commander.get_node("gripper").attrs["gripper_finger_distance"].value == pytest.approx(0.75) and
                commander.get_node("hand_camera").attrs.get("cam_rgb_width") is not None and
                commander.get_node("hand_camera").attrs["cam_rgb_width"].value == 1280)
    assert commander.get_id_from_name("gripper") == gripper_id
    assert rt_api(commander).get_translation(commander.get_id_from_name("arm"), gripper_id) == \
        pytest.approx([300.0, 0.0, 400.0])

    # The commander writes a target pose (a new attribute) and then a finger distance (.value).
    command = commander.get_node(gripper_id)
    command.attrs["target"] = Attribute([400.0, 50.0, 300.0, 3.14, 0.0, 1.57], 31)
    assert commander.update_node(command)
    assert wait(lambda: len(targets) == 1)
    assert targets[0] == pytest.approx([400.0, 50.0, 300.0, 3.14, 0.0, 1.57], rel=1e-6)
    command = commander.get_node(gripper_id)
    command.attrs["gripper_target_finger_distance"].value = 0.6
    assert commander.update_node(command)
    assert wait(lambda: len(finger_goals) == 1)
    assert finger_goals[0] == pytest.approx(0.6, rel=1e-6)
    assert len(targets) == 1, "a finger command is not read as a new target"


def test_gen3_dsr_writes_its_camera_frames_as_uint8_arrays(gen3):
    g, _ = gen3
    camera = g.get_node("hand_camera")
    camera.attrs["cam_rgb"] = Attribute(np.zeros((480, 640, 3), np.uint8), 30)
    camera.attrs["cam_depth"] = Attribute(np.zeros((270, 480, 3), np.uint8), 30)
    assert g.update_node(camera)
    frame = np.full((480, 640, 3), 7, np.uint8)
    camera = g.get_node("hand_camera")
    camera.attrs["cam_rgb"].value = frame
    assert g.update_node(camera)
    value = g.get_node("hand_camera").attrs["cam_rgb"].value
    # A reader (eye_control_dsr below) rebuilds the frame from the bytes.
    assert np.array_equal(np.frombuffer(value, np.uint8).reshape(480, 640, 3), frame)


# ---------------------------------------------------------------------------------------------
# robocomp/robocomp-shadow, agents/eye_control_dsr/src/specificworker.py
#
# The agent that turns the robot's camera servo towards the person it follows. It starts
# DSRGraph(0, "eye_control", 911), an rt_api, and connects UPDATE_NODE, DELETE_NODE, UPDATE_EDGE
# and DELETE_EDGE. Every period it gets "giraff_camera_realsense" by name and turns attrs
# "cam_rgb" (bytes) with "cam_rgb_width" and "cam_rgb_height" into an image
# (np.frombuffer(..., uint8).reshape(h, w, 3)). Its UPDATE_NODE slot: for a node of type
# "intention" it keeps the id, gets the node and parses attrs "current_intention" (a JSON string
# such as {"FOLLOW_PEOPLE": {"person_node_id": <id>}}) to learn which person to follow; for a node
# of type "person" that is the followed one, it reads the servo's state from node "servo"
# (servo_pos, servo_speed, servo_moving), the person's "person_pixel_x" and "distance_to_robot",
# the robot's "robot_ref_rot_speed" from node "robot", and writes a new aim to "servo" as
# servo_ref_pos and servo_ref_speed = Attribute(float(...), 911) followed by update_node. Its
# UPDATE_EDGE slot makes the destination of an "interacting" edge the followed person; its
# DELETE_EDGE slot, for an "interacting" edge, asks get_edge(from, to, "following_action") and,
# when that is None, stops following and re-centres the servo (servo_ref_pos 0.1, servo_ref_speed
# 0.0, written the same way); its DELETE_NODE slot stops following when the intention node goes.
# For its plot it gets the people by type, the node "robot", and reads rt_translation from
# rt_api.get_edge_RT(robot_node, person.id).
# ---------------------------------------------------------------------------------------------

class EyeControl:
    """The eye_control agent's state and slots, as we describe them above (not its code)."""

    def __init__(self, g):
        self.g = g
        self.chased = None
        self.intention_id = None
        self.aims = []  # (servo_ref_pos, servo_ref_speed) written
        self.person_updates = []
        self.reads = []  # what a person update read: servo state, then person and robot values
        self.last_pixel_x = None
        signals.connect(g, signals.UPDATE_NODE, self.update_node)
        signals.connect(g, signals.DELETE_NODE, self.delete_node)
        signals.connect(g, signals.UPDATE_EDGE, self.update_edge)
        signals.connect(g, signals.DELETE_EDGE, self.delete_edge)

    def aim(self, pos, speed):
        servo = self.g.get_node("servo")
        servo.attrs["servo_ref_pos"] = Attribute(float(pos), 911)
        servo.attrs["servo_ref_speed"] = Attribute(float(speed), 911)
        if self.g.update_node(servo):
            self.aims.append((pos, speed))

    def update_node(self, id, type):
        if type == "intention":
            self.intention_id = id
            intention = json.loads(self.g.get_node(id).attrs["current_intention"].value)
            (kind, data), = intention.items()
            if kind in ("FOLLOW_PEOPLE", "TALKING_WITH_PEOPLE"):
                self.chased = int(data["person_node_id"])
        elif type == "person":
            self.person_updates.append(id)
            servo = self.g.get_node("servo")
            servo_pos = servo.attrs["servo_pos"].value
            self.reads.append(("servo", servo_pos, servo.attrs["servo_speed"].value, servo.attrs["servo_moving"].value))
            person = self.g.get_node(id)
            if self.chased is None or person is None or person.id != self.chased:
                return
            pixel_x = person.attrs["person_pixel_x"].value
            if pixel_x == self.last_pixel_x:
                return
            self.last_pixel_x = pixel_x
            distance = person.attrs["distance_to_robot"].value
            rot_speed = self.g.get_node("robot").attrs["robot_ref_rot_speed"].value
            self.reads.append(("person", pixel_x, distance, rot_speed))
            error = float(np.arctan2(pixel_x - 240, 382))
            self.aim(servo_pos - error, abs(error) * 1000.0 / distance)

    def delete_node(self, id):
        if id == self.intention_id:
            self.chased = None
            self.intention_id = None

    def update_edge(self, fr, to, type):
        if type == "interacting":
            self.chased = to

    def delete_edge(self, fr, to, type):
        if type == "interacting" and self.g.get_edge(fr, to, "following_action") is None:
            self.chased = None
            self.aim(0.1, 0.0)


@pytest.fixture
def eye(tmp_path):
    world = world_file(tmp_path, [
        {"name": "robot", "type": "omnirobot", "attrs": {"robot_ref_rot_speed": {"float": 0.2}}},
        {"name": "servo", "type": "servo", "attrs": {"servo_pos": {"float": 0.3}, "servo_speed": {"float": 0.0},
                                                      "servo_moving": False}},
        {"name": "giraff_camera_realsense", "type": "rgbd"}])
    g = DSRGraph(0, "eye_control", 911, world, domain=DOMAIN, join_wait=0.5)
    peer = DSRGraph(0, "people_and_camera", 912, world, domain=DOMAIN)
    yield g, peer
    peer.close()
    g.close()


def test_eye_control_dsr_call_sequence(eye):
    g, peer = eye
    rt = rt_api(g)
    agent = EyeControl(g)
    servo_id = peer.get_id_from_name("servo")
    servo_seen = []
    signals.connect(peer, signals.UPDATE_NODE_ATTR,
                    lambda id, names: servo_seen.append(sorted(names)) if id == servo_id else None)

    # The camera agent publishes a frame as bytes with its size; eye_control rebuilds the image.
    frame = np.arange(4 * 6 * 3, dtype=np.uint8).reshape(4, 6, 3)
    camera = peer.get_node("giraff_camera_realsense")
    camera.attrs["cam_rgb"] = Attribute(frame.tobytes(), 912)
    camera.attrs["cam_rgb_width"] = Attribute(6, 912)
    camera.attrs["cam_rgb_height"] = Attribute(4, 912)
    assert peer.update_node(camera)
    assert wait(lambda: "cam_rgb" in g.get_node("giraff_camera_realsense").attrs)
    camera = g.get_node("giraff_camera_realsense")
    image = np.frombuffer(camera.attrs["cam_rgb"].value, np.uint8).reshape(
        camera.attrs["cam_rgb_height"].value, camera.attrs["cam_rgb_width"].value, 3)
    assert np.array_equal(image, frame)

    # The people agent creates a person under the robot; eye_control hears of it, follows nobody yet.
    person = Node(912, "person", "person_3")
    person.attrs["person_pixel_x"] = Attribute(300, 912)
    person.attrs["distance_to_robot"] = Attribute(1500.0, 912)
    person_id = peer.insert_node(person)
    robot = peer.get_node("robot")
    assert rt_api(peer).insert_or_assign_edge_RT(robot, person_id, [1200.0, 900.0, 0.0], [0.0, 0.0, 0.4])
    assert wait(lambda: person_id in agent.person_updates)
    assert agent.aims == [] and agent.chased is None
    kind, servo_pos, servo_speed, servo_moving = agent.reads[0]
    assert kind == "servo" and servo_pos == pytest.approx(0.3, rel=1e-6) and servo_speed == 0.0
    assert servo_moving is False

    # An intention to follow that person: the UPDATE_NODE slot parses its JSON.
    intention = Node(912, "intention", "intention_follow")
    intention.attrs["current_intention"] = Attribute(json.dumps({"FOLLOW_PEOPLE": {"person_node_id": person_id}}), 912)
    intention_id = peer.insert_node(intention)
    assert wait(lambda: agent.chased == person_id)
    assert agent.intention_id == intention_id

    # The plot: people by type, the robot by name, each person's RT edge from the robot.
    robot_node = g.get_node("robot")
    people = g.get_nodes_by_type("person")
    assert [p.id for p in people] == [person_id]
    tx, ty, tz = rt.get_edge_RT(robot_node, people[0].id).attrs["rt_translation"].value
    assert (round(tx), round(ty), round(tz)) == (1200, 900, 0)

    # The intention goes: DELETE_NODE with its id stops the following.
    assert peer.delete_node(intention_id)
    assert wait(lambda: agent.chased is None and agent.intention_id is None)

    # An "interacting" edge from the robot makes its destination the followed person.
    assert peer.insert_or_assign_edge(Edge(person_id, robot.id, "interacting", 912))
    assert peer.insert_or_assign_edge(Edge(person_id, robot.id, "following_action", 912))
    assert wait(lambda: agent.chased == person_id)

    # Removing "interacting" while "following_action" remains: still no re-centring.
    assert peer.delete_edge(robot.id, person_id, "interacting")
    assert wait(lambda: g.get_edge(robot.id, person_id, "interacting") is None)
    time.sleep(0.3)
    assert agent.aims == [] and agent.chased == person_id

    # Again without "following_action": the DELETE_EDGE slot re-centres the servo.
    assert peer.delete_edge(robot.id, person_id, "following_action")
    assert peer.insert_or_assign_edge(Edge(person_id, robot.id, "interacting", 912))
    assert wait(lambda: g.get_edge(robot.id, person_id, "interacting") is not None)
    assert peer.delete_edge(robot.id, person_id, "interacting")
    assert wait(lambda: agent.aims == [(0.1, 0.0)])
    assert agent.chased is None
    servo = g.get_node("servo")
    assert servo.attrs["servo_ref_pos"].value == pytest.approx(0.1, rel=1e-6)
    assert servo.attrs["servo_ref_speed"].value == 0.0
    assert servo.attrs["servo_pos"].value == pytest.approx(0.3, rel=1e-6), "the servo's state is untouched"

    # The servo driver (here the peer) sees the new aim.
    assert wait(lambda: ["servo_ref_pos", "servo_ref_speed"] in servo_seen)
    assert peer.get_node("servo").attrs["servo_ref_pos"].value == pytest.approx(0.1, rel=1e-6)


def test_eye_control_dsr_tracks_a_person_whose_attributes_change(eye):
    g, peer = eye
    agent = EyeControl(g)
    person = Node(912, "person", "person_5")
    person.attrs["person_pixel_x"] = Attribute(240, 912)
    person.attrs["distance_to_robot"] = Attribute(2000.0, 912)
    person_id = peer.insert_node(person)
    robot = peer.get_node("robot")
    assert peer.insert_or_assign_edge(Edge(person_id, robot.id, "interacting", 912))
    assert wait(lambda: agent.chased == person_id)
    updates_before = len(agent.person_updates)

    # The person moves in the image: pydsr delivers UPDATE_NODE(person_id, "person").
    person = peer.get_node(person_id)
    person.attrs["person_pixel_x"].value = 340
    assert peer.update_node(person)
    assert wait(lambda: len(agent.person_updates) > updates_before, timeout=3.0)
    assert wait(lambda: len(agent.aims) == 1)
    assert agent.reads[-1] == ("person", 340, pytest.approx(2000.0), pytest.approx(0.2, rel=1e-6))
    pos, speed = agent.aims[0]
    assert pos == pytest.approx(0.3 - float(np.arctan2(100, 382)), rel=1e-5)
    assert g.get_node("servo").attrs["servo_ref_pos"].value == pytest.approx(pos, rel=1e-5)
