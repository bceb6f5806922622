#!/usr/bin/env python3
"""The page of `quiver bench all`: reads its bench.json, draws the plots with matplotlib (SVG and
PNG) and writes index.html beside them. Embedded in quiver (tools/bench/CMakeLists.txt).

Usage: plot_bench.py BENCH.json OUT_DIR
"""
import html
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)


def results(report, name, side):
    for run in report["runs"]:
        if run["name"] == name and run["side"] == side:
            return run.get("results", [])
    return []


def save(fig, out, name):
    fig.tight_layout()
    for ext in ("svg", "png"):
        fig.savefig(os.path.join(out, f"{name}.{ext}"), dpi=110)
    plt.close(fig)


def plot_peers(report, out):
    rows = [s for s in report["summary"] if s.get("ratio", 0) > 0]
    if not rows:
        return None
    better = [s["ratio"] if s["better"] == "higher" else 1 / s["ratio"] for s in rows]
    fig, ax = plt.subplots(figsize=(9, 0.5 * len(rows) + 1.6))
    ax.barh(range(len(rows)), better, color=["tab:green" if b >= 1 else "tab:red" for b in better])
    ax.set_xscale("log")
    ax.axvline(1, color="black", lw=1)
    ax.set_yticks(range(len(rows)), [f'{s["figure"]}\nagainst {s["peer"]}' for s in rows], fontsize=8)
    ax.invert_yaxis()
    for i, b in enumerate(better):
        ax.text(b, i, f" {b:.2f}x", va="center", fontsize=8)
    ax.set_xlabel("times better than the peer (right of 1: Quiver better; log scale)")
    ax.set_title("Quiver against its peers, measured in the same run")
    save(fig, out, "peers")
    return "peers", "Quiver against each peer: the ratio of each figure, turned so that more is better."


def plot_stages(report, out):
    stages = next((r["stages_us_p50"] for r in results(report, "dds", "quiver") if "stages_us_p50" in r), None)
    if not stages:
        return None
    order = ["commit_and_encode", "sign", "dds_write", "delivery_and_wakeup", "take", "decode", "admission",
             "bookkeeping", "merge_and_events"]
    parts = [(k, stages[k]) for k in order if stages.get(k, 0) > 0]
    oneway = next((r.get("oneway_latency_us") for r in results(report, "dds", "ddsperf")), None)
    fig, ax = plt.subplots(figsize=(9, 3.2))
    left = 0
    for i, (k, v) in enumerate(parts):
        ax.barh(0, v, left=left, color=plt.cm.tab10(i % 10), label=f"{k} {v:g}")
        left += v
    if oneway:
        ax.barh(1, oneway, color="grey", label=f"ddsperf one-way {oneway:g}")
    ax.set_yticks([0, 1] if oneway else [0], ["Quiver, one change"] + (["ddsperf, 64 B"] if oneway else []))
    ax.set_xlabel("microseconds (medians)")
    ax.legend(fontsize=7, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.45))
    ax.set_title("Where a change's latency goes (quiver bench dds --stages)")
    save(fig, out, "stages")
    return "stages", "The latency of one change by stage, beside Cyclone's own one-way latency."


def plot_scale(report, out):
    rows = sorted((r for r in results(report, "scale", "quiver") if "bytes_per_op_per_agent" in r),
                  key=lambda r: r["agents"])
    if not rows:
        return None
    n = [r["agents"] for r in rows]
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.loglog(n, [r["bytes_per_op_per_agent"] for r in rows], "o-", label="bytes per op per agent")
    ax.loglog(n, [r["idle_bytes_per_s_per_agent"] for r in rows], "s--", label="idle bytes/s per agent")
    ax.set_xlabel("agents (simulator)")
    ax.legend()
    ax.set_title("Cost per agent as agents are added (quiver bench scale)")
    save(fig, out, "scale")
    return "scale", "What each agent sends as the number of agents grows: flat is the goal."


def plot_footprint(report, out):
    rows = [r for r in results(report, "footprint", "quiver") if "rss_kb_p50" in r]
    if not rows:
        return None
    fig, ax = plt.subplots(figsize=(9, 0.45 * len(rows) + 1.4))
    y = range(len(rows))
    anon = [r["rss_anon_kb_p50"] / 1024 for r in rows]
    files = [r["rss_file_kb_p50"] / 1024 for r in rows]
    ax.barh(y, anon, label="anonymous (heap, stacks)")
    ax.barh(y, files, left=anon, label="files (libraries)")
    ax.set_yticks(y, [f'{r["variant"]} ({r["executable"]})' for r in rows], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlabel("resident MB (median)")
    ax.legend(fontsize=8)
    ax.set_title("Agent processes at rest (quiver bench footprint)")
    save(fig, out, "footprint")
    return "footprint", "Resident memory of agent processes after they settle."


def host_text(host):
    return f"{host.get('cores', '?')} cores, {host.get('machine', '?')}, Linux {host.get('kernel', '?')}"


def cell(v):
    return html.escape(f"{v:g}" if isinstance(v, float) else str(v))


def main():
    path, out = sys.argv[1], sys.argv[2]
    with open(path) as f:
        report = json.load(f)
    plots = [p for p in (plot_peers(report, out), plot_stages(report, out), plot_scale(report, out),
                         plot_footprint(report, out)) if p]
    page = ["<!doctype html><meta charset=utf-8><title>quiver bench all</title>",
            "<style>body{font-family:sans-serif;max-width:60em;margin:auto}td,th{padding:2px 8px;"
            "text-align:left}table{border-collapse:collapse}tr:nth-child(even){background:#eee}</style>",
            f"<h1>quiver bench all</h1><p>{cell(report.get('started'))} to {cell(report.get('finished'))}, "
            f"{cell(host_text(report.get('host', {})))}"
            f"{', quick sizes (a check, not figures to quote)' if report.get('quick') else ''}. "
            "The figures: <a href=bench.json>bench.json</a>.</p>",
            "<h2>Quiver and its peers</h2><table><tr><th>figure</th><th>Quiver</th><th>peer</th><th>peer's</th>"
            "<th>Quiver / peer</th><th>better</th></tr>"]
    for s in report["summary"]:
        page.append("<tr>" + "".join(f"<td>{cell(s.get(k, ''))}</td>"
                                     for k in ("figure", "quiver", "peer", "peer_value", "ratio", "better")) + "</tr>")
    page.append("</table>")
    for name, caption in plots:
        page.append(f"<h2>{html.escape(caption)}</h2><img src={name}.svg alt='{name}' style='max-width:100%'>")
    page.append("<h2>Every command</h2><table><tr><th>benchmark</th><th>side</th><th>seconds</th><th>exit</th></tr>")
    for run in report["runs"]:
        status = f"absent: {run['absent']}" if "absent" in run else run.get("exit", "")
        page.append(f"<tr><td>{cell(run['name'])}</td><td>{cell(run['side'])}</td>"
                    f"<td>{cell(run.get('seconds', ''))}</td><td>{cell(status)}</td></tr>")
    page.append("</table>")
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write("\n".join(page) + "\n")


if __name__ == "__main__":
    main()
