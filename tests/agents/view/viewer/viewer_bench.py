"""The viewer's page under load, measured in headless Chromium (docs/viewer.md, "Performance").

1. Frame rate while 900 RT updates/s arrive: two people x 15 joints x 30 Hz written by a Python
   agent over DDS (loopback) while the page shows them; the page's requestAnimationFrame rate is
   sampled every second, and the joints must really move in the 3D view.
2. A 10k-node world (10k nodes, 10k symbolic edges) served by `quiver view --world`: the time
   from navigation start to the first drawn graph (quiver.readyMs).
3. A change's way to the page: from a Python agent's commit to the node appearing on the page
   (quiver.appearedAt), over 20 changes (target: within 200 ms).

Prints one JSON line per run and then the medians. Needs PYTHONPATH=build/python/module and runs
DDS on loopback (inside `unshare --net` in CI).
  /usr/bin/python3 tests/agents/view/viewer/viewer_bench.py --runs 3
"""
import argparse
import json
import os
import statistics
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import quiver  # noqa: E402
from browser import chromium, wait_for  # noqa: E402
from viewer_procs import make_world, move_people, start_view, stop  # noqa: E402


def fps_run(domain, seconds):
    with quiver.Agent("tracker", domain=domain) as a:
        a.write(lambda t: make_world(t, people=2))
        view, url = start_view(["--domain", str(domain)])
        driver = chromium()
        try:
            driver.get(url)
            wait_for(driver, "quiver.loadedMs !== null && quiver.objects3d() >= 33", timeout_s=20)
            before = driver.execute_script("return quiver.worldPosition('p1_head')")
            result = {}
            th = threading.Thread(target=lambda: result.update(updates=move_people(a, 2, 30, seconds)))
            th.start()
            samples = []
            time.sleep(1.5)
            while th.is_alive():
                samples.append(driver.execute_script("return quiver.fps"))
                time.sleep(1.0)
            th.join()
            after = driver.execute_script("return quiver.worldPosition('p1_head')")
            moved = before != after
            changes = driver.execute_script("return quiver.changes")
        finally:
            driver.quit()
            stop(view)
    return {"bench": "viewer_fps", "rt_updates_per_s": round(result["updates"] / seconds), "fps_median": statistics.median(samples),
            "fps_min": min(samples), "messages_applied": changes, "joints_moved": moved}


def latency_run(domain, changes=20):
    with quiver.Agent("writer", domain=domain) as a:
        a.write(lambda t: make_world(t, people=1))
        view, url = start_view(["--domain", str(domain)])
        driver = chromium()
        try:
            driver.get(url)
            wait_for(driver, "quiver.loadedMs !== null && quiver.nodeNames().includes('p0_head')", timeout_s=20)
            latencies = []
            for i in range(changes):
                name = f"cup{i}"
                t_commit = time.time() * 1000
                a.write(lambda t, name=name: t.insert_edge(t.create_node("cup", name), "kitchen", "in"))
                appeared = wait_for(driver, f"quiver.appearedAt['{name}']", timeout_s=30)
                latencies.append(appeared - t_commit)
                time.sleep(0.1)
        finally:
            driver.quit()
            stop(view)
    return {"bench": "viewer_latency", "changes": changes, "latency_ms_median": round(statistics.median(latencies), 1),
            "latency_ms_max": round(max(latencies), 1)}


def big_world(path, n):
    nodes = [{"name": "world", "type": "world"}] + [{"name": f"n{i}", "type": f"t{i % 12}"} for i in range(n - 1)]
    edges = [{"from": f"n{i}", "to": f"n{(i * 7 + 1) % (n - 1)}", "type": f"e{i % 5}"} for i in range(n - 1)]
    edges.append({"from": "n0", "to": "world", "type": "in"})
    with open(path, "w") as f:
        json.dump({"quiver_world": 1, "nodes": nodes, "edges": edges}, f)


def load_run(path, n):
    view, url = start_view(["--world", path])
    driver = chromium()
    try:
        driver.get(url)
        ready = wait_for(driver, "quiver.readyMs", timeout_s=60)
        count = driver.execute_script("return quiver.nodes.size")
        fetched = driver.execute_script("return quiver.loadedMs")
    finally:
        driver.quit()
        stop(view)
    return {"bench": "viewer_load", "nodes": count, "ready_ms": round(ready, 1), "snapshot_and_build_ms": round(fetched, 1)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=8)
    ap.add_argument("--nodes", type=int, default=10000)
    ap.add_argument("--domain", type=int, default=40)
    args = ap.parse_args()
    fps, ready, latency = [], [], []
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "big.json")
        big_world(path, args.nodes)
        for r in range(args.runs):
            f = fps_run(args.domain, args.seconds)
            print(json.dumps(f), flush=True)
            fps.append(f["fps_median"])
            ok = ok and f["joints_moved"] and f["messages_applied"] > 0
            l = load_run(path, args.nodes)
            print(json.dumps(l), flush=True)
            ready.append(l["ready_ms"])
            ok = ok and l["nodes"] == args.nodes
            d = latency_run(args.domain)
            print(json.dumps(d), flush=True)
            latency.append(d["latency_ms_max"])
    print(json.dumps({"bench": "viewer", "fps_median": statistics.median(fps), "target_fps": 30,
                      "ready_ms_median": statistics.median(ready), "target_ready_ms": 2000, "nodes": args.nodes,
                      "latency_ms_max_median": statistics.median(latency), "target_latency_ms": 200}))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
