"""A Python agent and the C++ `quiver agent` process converge over DDS (loopback)."""
import json
import subprocess
import threading

import quiver

WORLD = {
    "quiver_world": 1,
    "nodes": [
        {"name": "world", "type": "world"},
        {"name": "robot", "type": "robot", "attrs": {"battery": 0.75, "pos": {"vec3f": [1, 2, 3]}}},
        {"name": "kitchen", "type": "room"},
    ],
    "edges": [{"from": "robot", "to": "kitchen", "type": "in"}],
    "rt": [{"parent": "world", "child": "robot", "translation": [1, 0, 0], "rotation": [1, 0, 0, 0]}],
}


def test_python_and_cpp_agents_converge(quiver_bin, tmp_path):
    world = tmp_path / "world.json"
    world.write_text(json.dumps(WORLD))
    proc = subprocess.Popen(
        [quiver_bin, "agent", "--name", "cpp-agent", "--domain", "96", "--world", str(world),
         "--status-ms", "100", "--run-for", "30", "--join-wait", "0.2"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    statuses = []
    reader = threading.Thread(target=lambda: [statuses.append(json.loads(l)) for l in proc.stdout
                                              if l.startswith("{")], daemon=True)
    reader.start()
    try:
        with quiver.Agent("py-agent", domain=96) as a:
            # The C++ agent's world reaches the Python replica, values typed as in the file.
            assert a.wait_until(lambda g: g.find_node("robot") is not None and g.has_edge("robot", "kitchen", "in"),
                                timeout=20)
            assert a.call(lambda g: g.value("robot", "pos").type) == "vec3f"
            assert a.call(lambda g: g.rt_parent("robot") == g.node("world"))
            # A Python change reaches the C++ replica: its status line shows our digest.

            def add(t):
                mug = t.create_node("mug", "mug", {"full": True})
                t.insert_edge(mug, t_kitchen[0], "in")
            t_kitchen = [a.call(lambda g: g.node("kitchen"))]
            a.write(add)
            a.write(lambda t: t.set("robot", "battery", 0.5))

            def converged(g):
                if not statuses:
                    return False
                last = statuses[-1]
                return last["digest"] == g.digest() and last["nodes"] == g.node_count == 4
            assert a.wait_until(converged, timeout=20), statuses[-1:]
            assert statuses[-1]["peers"] >= 1
    finally:
        proc.terminate()
        proc.wait(timeout=10)
