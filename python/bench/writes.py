#!/usr/bin/env python3
"""Random attribute writes from Python: 1000 nodes x 10 double attributes, writes in transactions
of 100, against the same workload run by a C++ loop (quiver._bench_cpp_writes). Prints the median
of --runs runs of each and their ratio (the Python per-call overhead).

    PYTHONPATH=build/python/module /usr/bin/python3 python/bench/writes.py [--runs 5] [--writes 200000]
"""
import argparse
import random
import statistics
import time

import quiver


def python_run(nodes, attrs, writes, batch, seed):
    g = quiver.Graph("bench")
    names = [f"a{i}" for i in range(attrs)]
    with g.transaction() as t:
        ids = [t.create_node("thing", f"n{n}", {a: 0.0 for a in names}) for n in range(nodes)]
    rng = random.Random(seed)
    # The random choices are drawn first (as the C++ loop does): only the writes are timed.
    work = [(ids[rng.randrange(nodes)], names[rng.randrange(attrs)], rng.random()) for _ in range(writes)]
    chunks = [work[i:i + batch] for i in range(0, writes, batch)]
    start = time.perf_counter()
    for chunk in chunks:
        t = g.transaction()
        s = t.set
        for node, name, value in chunk:
            s(node, name, value)
        t.commit()
    elapsed = time.perf_counter() - start
    assert g.node_count == nodes
    return writes / elapsed


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--nodes", type=int, default=1000)
    p.add_argument("--attrs", type=int, default=10)
    p.add_argument("--writes", type=int, default=200_000)
    p.add_argument("--batch", type=int, default=100)
    p.add_argument("--runs", type=int, default=5)
    a = p.parse_args()
    py = [python_run(a.nodes, a.attrs, a.writes, a.batch, seed) for seed in range(1, a.runs + 1)]
    cpp = [quiver._bench_cpp_writes(a.nodes, a.attrs, a.writes, a.batch, seed) for seed in range(1, a.runs + 1)]
    py_med, cpp_med = statistics.median(py), statistics.median(cpp)
    print(f"workload: {a.nodes} nodes x {a.attrs} attributes, {a.writes} random double writes, "
          f"transactions of {a.batch}, median of {a.runs} runs")
    print(f"python: {py_med:,.0f} writes/s   (runs: {', '.join(f'{x:,.0f}' for x in py)})")
    print(f"c++:    {cpp_med:,.0f} writes/s   (runs: {', '.join(f'{x:,.0f}' for x in cpp)})")
    print(f"ratio c++/python: {cpp_med / py_med:.2f}x   "
          f"(python per write {1e6 / py_med:.2f} us, c++ {1e6 / cpp_med:.2f} us, "
          f"overhead {1e6 / py_med - 1e6 / cpp_med:.2f} us per call)")


if __name__ == "__main__":
    main()
