"""Processes for the viewer's tests and benchmark: `quiver view` / `quiver record` on a DDS domain
(loopback configuration), and a Python writer agent that makes a small robot world."""
import math
import os
import re
import subprocess
import time

import quiver

QUIVER = os.environ.get("QUIVER_BIN", "build/quiver")
JOINTS = ["head", "neck", "torso", "l_shoulder", "l_elbow", "l_hand", "r_shoulder", "r_elbow", "r_hand",
          "l_hip", "l_knee", "l_foot", "r_hip", "r_knee", "r_foot"]


def start_quiver(args, url_prefix="quiver view: "):
    """Starts a quiver command; returns (process, first line it printed that starts with url_prefix)."""
    p = subprocess.Popen([QUIVER] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = p.stdout.readline()
    if not line.startswith(url_prefix):
        p.kill()
        raise AssertionError(f"{args}: printed {line!r}, stderr {p.stderr.read()!r}")
    return p, line


def start_view(args):
    p, line = start_quiver(["view", "--listen", "127.0.0.1:0"] + args)
    return p, re.search(r"http://\S+", line).group(0)


def stop(p):
    p.terminate()
    try:
        p.wait(timeout=10)
    except subprocess.TimeoutExpired:
        p.kill()
        p.wait()


def make_world(t, people=1):
    """A world, a room, a robot in it (with a shape), and people of 15 capsule joints each."""
    world = t.create_node("world", "world")
    room = t.create_node("room", "kitchen")
    robot = t.create_node("robot", "robot", {"battery": 0.75, "shape": "box", "shape_size": quiver.Value("vec3f", [0.5, 0.4, 0.3])})
    t.insert_edge(robot, room, "in")
    t.set_rt(world, room, translation=[0, 0, 0])
    t.set_rt(room, robot, translation=[1, 0, 0.15])
    for k in range(people):
        person = t.create_node("person", f"person{k}")
        t.insert_edge(person, room, "in")
        t.set_rt(room, person, translation=[2 + k, 1, 0])
        for j in JOINTS:
            n = t.create_node("joint", f"p{k}_{j}", {"shape": "capsule", "shape_radius": 0.05, "shape_length": 0.2})
            t.set_rt(person, n, translation=joint_pose(j, 0.0))


def joint_pose(j, phase):
    i = JOINTS.index(j)
    return [0.3 * math.cos(i) + 0.05 * math.sin(phase + i), 0.3 * math.sin(i), 0.1 * i + 0.05 * math.cos(phase)]


def move_people(agent, people, hz, seconds, stamp0=1):
    """Moves every joint of every person at `hz` for `seconds`: one transaction per person per
    tick (15 RT updates). Returns the number of RT updates made."""
    period = 1.0 / hz
    n = 0
    t0 = time.monotonic()
    tick = 0
    while time.monotonic() - t0 < seconds:
        phase = tick * 0.2
        for k in range(people):
            def move(t, k=k, phase=phase, stamp=stamp0 + tick):
                for j in JOINTS:
                    t.set_rt(f"person{k}", f"p{k}_{j}", translation=joint_pose(j, phase), stamp=stamp)
            agent.write(move)
            n += len(JOINTS)
        tick += 1
        time.sleep(max(0.0, t0 + tick * period - time.monotonic()))
    return n
