#!/usr/bin/python3
"""Draws `quiver bench scale` JSON lines as log-log curves (PNG and SVG): bytes and messages per
op per agent, idle bytes per second per agent, protocol state per replica and the time to converge
after a partition heals, against the number of agents, one curve per input file (e.g. today's
protocol and a new one, side by side). A panel whose figure no input has is left out.

    build/quiver bench scale > scale.jsonl
    scripts/plot_scale.py scale.jsonl [LABEL=other.jsonl ...] -o docs/scale   # docs/scale.png, .svg
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_lines(path):
    rows = []
    with (sys.stdin if path == "-" else open(path)) as f:
        for k, line in enumerate(f, 1):
            line = line.strip()
            if not line.startswith("{"):
                continue
            try:
                j = json.loads(line)
            except json.JSONDecodeError as e:
                sys.exit(f"plot_scale: {path}:{k}: not JSON: {e}")
            if j.get("bench") == "scale":
                rows.append(j)
    if not rows:
        sys.exit(f"plot_scale: {path}: no `quiver bench scale` lines")
    return sorted(rows, key=lambda j: j["agents"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("inputs", nargs="+", help="FILE or LABEL=FILE (- for stdin)")
    ap.add_argument("-o", "--out", required=True, help="output path without extension")
    a = ap.parse_args()
    panels = [("bytes_per_op_per_agent", "bytes per op per agent", None),
              ("messages_per_op_per_agent", "messages per op per agent", None),
              ("idle_bytes_per_s_per_agent", "idle bytes per second per agent", (1000, "target: 1 KB/s")),
              ("protocol_bytes_max", "protocol state per replica (bytes, largest)", (65536, "target: 64 KB")),
              ("heal_ms", "ms to converge after a partition heals", (2000, "target: 2 s"))]
    inputs = []
    for spec in a.inputs:
        label, _, path = spec.rpartition("=")
        inputs.append((label or path, read_lines(path)))
    panels = [p for p in panels if any(r.get(p[0], 0) > 0 for _, rows in inputs for r in rows)]
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.5), squeeze=False)
    axes = axes[0]
    for k, (label, rows) in enumerate(inputs):
        for ax, (key, _, _) in zip(axes, panels):
            points = [(r["agents"], r[key]) for r in rows if r.get(key, 0) > 0]
            if points:  # one colour per input in every panel
                ax.plot([p[0] for p in points], [p[1] for p in points], "o-", color=f"C{k}", label=label)
    for ax, (_, _, target) in zip(axes, panels):
        if target:
            ax.axhline(target[0], ls="--", color="grey", label=target[1] + " (issue 22)")
    for ax, (_, what, _) in zip(axes, panels):
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel("agents")
        ax.set_ylabel(what)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle("quiver bench scale (simulator: the samples DDS would carry)")
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(f"{a.out}.{ext}")
        print(f"{a.out}.{ext}")


if __name__ == "__main__":
    main()
