"""Plot ``fkcheck bench --json`` output: time per pose of each contender, log scale.

Usage: ``python benchmarks/plot_bench.py reports/bench.json reports/bench.png``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # after choosing the Agg backend

COLOURS = {"in-house": "tab:blue", "peer": "tab:orange", "bound": "tab:grey"}


def plot(data: dict, out: Path) -> None:
    """A horizontal bar per contender that ran: ns per pose, fastest at the top."""
    ran = [t for t in data["timings"] if t["us_per_pose"] is not None]
    ran.sort(key=lambda t: t["us_per_pose"], reverse=True)
    fig, ax = plt.subplots(figsize=(10, 0.45 * len(ran) + 1.6))
    ns = [t["us_per_pose"] * 1e3 for t in ran]
    ax.barh(
        [f"{t['name']} (n={t['n']:,})" for t in ran],
        ns,
        color=[COLOURS[t["kind"]] for t in ran],
    )
    for y, (t, value) in enumerate(zip(ran, ns, strict=True)):
        speedup = t["speedup_vs_fastest_peer"]
        time_ns = f"{value:,.0f}" if value >= 100 else f"{value:.3g}"
        label = f"{time_ns} ns" + (f"  ({speedup:.3g}× fastest peer)" if speedup else "")
        ax.text(value * 1.1, y, label, va="center", fontsize=8)
    ax.set_xscale("log")
    ax.set_xlim(min(ns) / 2, max(ns) * 2000)
    ax.set_xlabel("time per pose (ns, log scale; shorter is faster)")
    load = ", ".join(f"{v:.2f}" for v in data["machine"].get("load_average") or [])
    ax.set_title(
        f"fkcheck bench {data['model']}: N = {data['n']:,}, median of {data['repeat']} runs\n"
        f"{data['machine'].get('cpu')}, {data['machine'].get('cpus')} CPUs, load {load}",
        fontsize=10,
    )
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_bench.py BENCH.json OUT.png")
    plot(json.loads(Path(sys.argv[1]).read_text()), Path(sys.argv[2]))
