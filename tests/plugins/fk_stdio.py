"""An external FK program for the command-backend tests, run with sys.executable.

Reads CSV joint lines on stdin, prints 16 numbers per line (UR5, closed form).
The first argument picks a behaviour:

* ok: space-separated output; comma: comma-separated output;
  seven-digits: every number printed with 7 significant digits (``%.7g``);
* garbage: a word instead of a number; short: 15 numbers on the first line;
  missing: one line too few; nan: a NaN in the last pose;
* exit: status 3 with a message on stderr; echo-argv: its arguments on stderr, status 4;
* hang PIDFILE: sleeps, as does a child it starts; writes both pids to PIDFILE.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np
from ur5_closed_form import forward


def main() -> int:
    mode = sys.argv[1] if len(sys.argv) > 1 else "ok"
    if mode == "hang":
        # A grandchild holding stdout open too: the backend must kill the group.
        # Both pids go to the file named by the second argument.
        child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"])
        tmp = Path(sys.argv[2] + ".tmp")
        tmp.write_text(f"{os.getpid()} {child.pid}\n")
        tmp.replace(sys.argv[2])  # atomic: readers never see a half-written file
        time.sleep(600)
    if mode == "echo-argv":
        print("argv=" + "|".join(sys.argv[1:]), file=sys.stderr)
        return 4
    lines = [ln for ln in sys.stdin.read().splitlines() if ln.strip()]
    if mode == "exit":
        print("warming up", file=sys.stderr)
        print(f"fk_stdio: cannot handle {len(lines)} lines", file=sys.stderr)
        return 3
    q = np.array([[float(v) for v in ln.split(",")] for ln in lines]).reshape(-1, 6)
    T = forward(q)
    if mode == "nan":
        T[-1, 1, 1] = np.nan
    out = []
    for k, pose in enumerate(T):
        fmt = "{:.7g}" if mode == "seven-digits" else "{!r}"
        values = [fmt.format(v) for v in pose.ravel().tolist()]
        if mode == "garbage" and k == 1:
            values[5] = "zero"
        if mode == "short" and k == 0:
            values = values[:15]
        if mode == "arabic-digits" and k == 1:
            values[15] = "\u0661.\u0660"  # Arabic-Indic "1.0": not a number fkcheck reads
        out.append((", " if mode == "comma" else " ").join(values))
    if mode == "missing":
        out = out[:-1]
    sys.stdout.write("\n".join(out) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
