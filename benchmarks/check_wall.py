"""Wall time of whole ``fkcheck check`` runs, as a user starts them (a benchmark, not a test).

Each run is a fresh interpreter (imports, the URDF, every backend, the report
on stdout), timed from start to exit. The default case is the issue's: ``check
ur5 --samples 10000`` with every default backend, against the same check
with ``--against rtb-dh`` alone (the peer: the interpreter, imports and
sampling every run pays) measured in the same session, interleaved so that a
change in the machine's load touches both. ``--big`` adds the large checks
(``--samples 1000000``; ``--jacobian --samples 300000``), run once each, with
each backend's compared count from their JSON.

    python benchmarks/check_wall.py [--runs 7] [--big] [--json reports/check-wall.json]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CASES = {
    "every default backend": ["check", "ur5", "--samples", "10000"],
    "peer: rtb-dh only": ["check", "ur5", "--samples", "10000", "--against", "rtb-dh"],
}
BIG = {
    "1,000,000 samples": ["check", "ur5", "--samples", "1000000"],
    "300,000 samples with Jacobians": ["check", "ur5", "--jacobian", "--samples", "300000"],
}


def _run(argv: list[str], json_path: Path | None = None) -> tuple[float, int]:
    extra = ["--json", str(json_path)] if json_path is not None else []
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "fkcheck", *argv, *extra],
                          capture_output=True, text=True, check=False)  # fmt: skip
    return time.perf_counter() - start, done.returncode


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--big", action="store_true")
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args()
    _run(CASES["peer: rtb-dh only"])  # warm the file cache and the xacro expansion cache
    times: dict[str, list[float]] = {name: [] for name in CASES}
    codes: dict[str, set[int]] = {name: set() for name in CASES}
    for _ in range(args.runs):
        for name, argv in CASES.items():
            seconds, code = _run(argv)
            times[name].append(seconds)
            codes[name].add(code)
    result: dict[str, object] = {}
    for name in CASES:
        med = statistics.median(times[name])
        result[name] = {"median_s": round(med, 3), "runs_s": [round(t, 3) for t in times[name]],
                        "exit_codes": sorted(codes[name])}  # fmt: skip
        print(f"{name}: median {med:.2f} s over {args.runs} runs "
              f"(min {min(times[name]):.2f}, max {max(times[name]):.2f}), "
              f"exit {sorted(codes[name])}")  # fmt: skip
    ratio = statistics.median(times["every default backend"]) / statistics.median(
        times["peer: rtb-dh only"]
    )
    result["ratio_to_peer"] = round(ratio, 2)
    print(f"every default backend / rtb-dh only: {ratio:.2f}x")
    if args.big:
        with tempfile.TemporaryDirectory() as tmp:
            for name, argv in BIG.items():
                path = Path(tmp) / "out.json"
                seconds, code = _run(argv, path)
                doc = json.loads(path.read_text()) if path.exists() else {}
                compared = {b["name"]: b["subset"] or b["configurations"]
                            for b in doc.get("backends", [])}  # fmt: skip
                result[name] = {"wall_s": round(seconds, 1), "exit_code": code,
                                "configurations": doc.get("configurations"),
                                "compared": compared}  # fmt: skip
                print(f"{name}: {seconds:.1f} s, exit {code}, compared {compared}")
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
