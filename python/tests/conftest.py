"""Shared helpers of the Python tests: the module under test comes from PYTHONPATH (ctest points
it at build/python/module); the C++ CLI from QUIVER_BIN (else build/quiver)."""
import os
import pathlib
import sys
import time

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
if "quiver" not in sys.modules and not any("module" in p for p in sys.path):
    sys.path.insert(0, str(ROOT / "build" / "python" / "module"))

import quiver  # noqa: E402


def wait(pred, timeout=10.0):
    """Polls pred() every 20 ms until it is true or `timeout` seconds passed; its last value."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if pred():
            return True
        time.sleep(0.02)
    return pred()


@pytest.fixture
def quiver_bin():
    path = os.environ.get("QUIVER_BIN", str(ROOT / "build" / "quiver"))
    if not os.path.exists(path):
        pytest.fail(f"the quiver CLI is not built at {path}")
    return path


@pytest.fixture
def world():
    """A standalone graph with a world, a robot in a kitchen, and a hallway."""
    g = quiver.Graph("test")
    with g.transaction() as t:
        w = t.create_node("world", "world")
        r = t.create_node("robot", "robot", {"battery": 0.75})
        k = t.create_node("room", "kitchen")
        h = t.create_node("room", "hallway")
        t.insert_edge(r, k, "in")
        t.insert_edge(k, h, "transitable")
    return g


GRAMMAR = """
grammar test

types {
  robot
  room
}

allow attributes

rule changeRoom : active {
  { r:robot a:room b:room  r->a(in)  a->b(transitable) }
  =>
  { r:robot a:room b:room  r->b(in)  a->b(transitable) }
}
"""
