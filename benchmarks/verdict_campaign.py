"""Verdict campaign: published DH tables, every number wrong in turn, through map → paste → check.

Three arms from three vendors, each a published DH table and an independent
URDF (issue 30, "Done when"):

- ``ur5e``: Universal Robots' published DH table (models/ur5e.toml, the table only)
  against UR's own ROS 2 description (Universal_Robots_ROS2_Description 2.4.5,
  bundled as ``fkcheck:ur_description``), expanded once with ``fkcheck expand``.
- ``panda``: Franka's modified-DH table (Franka Control Interface documentation,
  models/panda.toml, the table and its ``[tool]`` only) against example-robot-data's
  ``panda_description/urdf/panda.urdf``.
- ``irb120``: ABB IRB 120 — the standard-DH table of ARTE (A Robotics Toolbox for
  Education, Arturo Gil, github.com/4rtur1t0/ARTE, robots/ABB/IRB120/parameters.m:
  θ offsets (0, -π/2, 0, 0, 0, π), d (0.290, 0, 0, 0.302, 0, 0.072), a (0, 0.270,
  0.070, 0, 0, 0), α (-π/2, 0, -π/2, π/2, -π/2, 0), joint ranges from its
  ``maxangle``) against the kinematics of ROS-Industrial's description
  (github.com/ros-industrial/abb, abb_irb120_support/urdf/irb120_3_58_macro.xacro at
  commit 59e17fb6: joint origins, axes and limits, the fixed links base, flange and
  tool0), transcribed below as a plain URDF without inertias or meshes.

(Unitree's Z1, in example-robot-data, was the first choice for the third vendor;
Unitree publishes its joint axes and positions, not a DH table, so a table would
have been this script's own.)

For each arm the table alone (no ``[urdf]``, no frames, no ``[check]``) is mapped
onto the URDF with ``fkcheck map``, the proposed block pasted after it, and the
result checked with ``fkcheck check --require table`` against the URDF readers —
first as published, then with one fault at a time: every number of the table
(each row's a, α, d, θ, and ``[base]``/``[tool]`` components) changed by 20
tolerances and by 1 mm / 0.001 rad, each joint reversed (``flip``), every angle
in degrees written as radians, and half a turn added to θ1, θn, αn (and α of the
first row in modified DH, ``[tool]`` rx and rz). Each outcome is one of:

- ``caught``: ``map`` finds no chain (exit 1), or the check fails;
- ``not-identifiable`` / ``not-covered``: the check passes or is unverified, and
  every changed number is reported so (honest);
- ``false-green``: the check passes or is unverified, and "table verified" is
  unqualified or a changed number is reported verified.

The table as published is a ``false-alarm`` when ``map`` or the check refuses it,
or a number of it is not identifiable for another reason than a choice among the
description's links (``competing`` links).

    python benchmarks/verdict_campaign.py [--json out.json] [--arms ur5e,panda]
        [--samples 32] [--against pinocchio-urdf] [--subset N --seed S]
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import random
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from fkcheck.cli.main import main as fkcheck_main
from fkcheck.core.tolerances import DEFAULT_TOL_POS_M, DEFAULT_TOL_ROT_RAD
from fkcheck.model.names import param_symbol
from fkcheck.model.read import load_model
from fkcheck.model.types import Model, Offset
from fkcheck.model.write import model_to_toml

ROOT = Path(__file__).resolve().parents[1]

#: The smaller fault, in tolerances (the issue's bar).
TOLERANCES = 20.0
#: The larger fault: 1 mm, 0.001 rad.
COARSE = {"m": 1e-3, "rad": 1e-3}

IRB120_TABLE = """\
name = "irb120"
description = "ABB IRB 120, standard DH"
source = "ARTE (A Robotics Toolbox for Education, Arturo Gil), robots/ABB/IRB120/parameters.m"
convention = "standard"
angle_unit = "rad"
"""
# ARTE's rows: (a, α, d, θ offset, lower, upper), metres and radians (maxangle ±165°,
# ±110°, -110…70°, ±160°, ±120°, ±400°).
_IRB120_ROWS = (
    (0.0, -math.pi / 2, 0.290, 0.0, -165, 165),
    (0.270, 0.0, 0.0, -math.pi / 2, -110, 110),
    (0.070, -math.pi / 2, 0.0, 0.0, -110, 70),
    (0.0, math.pi / 2, 0.302, 0.0, -160, 160),
    (0.0, -math.pi / 2, 0.0, 0.0, -120, 120),
    (0.0, 0.0, 0.072, math.pi, -400, 400),
)
IRB120_TABLE += "".join(
    f'\n[[joint]]\nname = "j{i + 1}"\na = {a!r}\nalpha = {alpha!r}\nd = {d!r}\n'
    f"theta = {theta!r}\nlimits = [{math.radians(lo)!r}, {math.radians(hi)!r}]\n"
    for i, (a, alpha, d, theta, lo, hi) in enumerate(_IRB120_ROWS)
)

# ROS-Industrial's abb_irb120_support irb120_3_58_macro.xacro (prefix ""), its
# kinematics only: (joint, parent, child, xyz, rpy, axis, lower, upper).
_IRB120_JOINTS = (
    ("joint_1", "base_link", "link_1", "0 0 0", "0 0 0", "0 0 1", -2.87979, 2.87979),
    ("joint_2", "link_1", "link_2", "0 0 0.29", "0 0 0", "0 1 0", -1.91986, 1.91986),
    ("joint_3", "link_2", "link_3", "0 0 0.27", "0 0 0", "0 1 0", -1.91986, 1.22173),
    ("joint_4", "link_3", "link_4", "0 0 0.07", "0 0 0", "1 0 0", -2.79253, 2.79253),
    ("joint_5", "link_4", "link_5", "0.302 0 0", "0 0 0", "0 1 0", -2.094395, 2.094395),
    ("joint_6", "link_5", "link_6", "0.072 0 0", "0 0 0", "1 0 0", -6.98132, 6.98132),
    ("base_link-base", "base_link", "base", "0 0 0", "0 0 0", "", 0, 0),
    ("joint_6-flange", "link_6", "flange", "0 0 0", "0 0 0", "", 0, 0),
    ("link_6-tool0", "flange", "tool0", "0 0 0", f"0 {math.pi / 2!r} 0", "", 0, 0),
)


def _irb120_urdf() -> str:
    links = ["base_link", *(f"link_{i}" for i in range(1, 7)), "base", "flange", "tool0"]
    out = ['<?xml version="1.0"?>', '<robot name="abb_irb120_3_58">']
    out += [f'  <link name="{name}"/>' for name in links]
    for name, parent, child, xyz, rpy, axis, lo, hi in _IRB120_JOINTS:
        kind = "revolute" if axis else "fixed"
        body = f'<origin xyz="{xyz}" rpy="{rpy}"/><parent link="{parent}"/><child link="{child}"/>'
        if axis:
            body += (
                f'<axis xyz="{axis}"/><limit effort="0" lower="{lo}" upper="{hi}" velocity="1"/>'
            )
        out.append(f'  <joint name="{name}" type="{kind}">{body}</joint>')
    return "\n".join([*out, "</robot>", ""])


@dataclass(frozen=True)
class Arm:
    """A published table and an independent description of the same arm.

    Attributes:
        name: Short name (``ur5e``).
        vendor: Who makes the arm.
        table: The model file as the user starts: the table alone.
        urdf: Prepares the URDF in a directory; returns what ``fkcheck map`` is given.
    """

    name: str
    vendor: str
    table: str
    urdf: Callable[[Path], str]


def _bundled_table(name: str) -> str:
    """A bundled model cut to its table (everything before ``[poses]``)."""
    text = (ROOT / "models" / f"{name}.toml").read_text(encoding="utf-8").split("\n[poses]")[0]
    for part in ("[urdf]", "[frames.", "[check]"):
        assert part not in text, f"{name}: the table part holds {part}"
    return text


def _ur5e_urdf(directory: Path) -> str:
    path = directory / "ur5e.urdf"
    if not path.exists():
        code, out = _fkcheck(["expand", "fkcheck:ur_description/urdf/ur.urdf.xacro",
                              "--arg", "ur_type=ur5e", "--arg", "name=ur5e",
                              "--package", "ur_description=fkcheck:ur_description",
                              "-o", str(path)])  # fmt: skip
        if code != 0:
            raise RuntimeError(f"fkcheck expand failed: {out}")
    return str(path)


def _irb120_file(directory: Path) -> str:
    path = directory / "irb120.urdf"
    path.write_text(_irb120_urdf(), encoding="utf-8")
    return str(path)


ARMS = {
    "ur5e": Arm("ur5e", "Universal Robots", _bundled_table("ur5e"), _ur5e_urdf),
    "panda": Arm("panda", "Franka Emika", _bundled_table("panda"),
                 lambda _d: "example-robot-data:panda_description/urdf/panda.urdf"),
    "irb120": Arm("irb120", "ABB", IRB120_TABLE, _irb120_file),
}  # fmt: skip


@dataclass(frozen=True)
class Fault:
    """One wrong table.

    Attributes:
        label: ``d1 +20 tol``, ``flip3``, ``θ1 +180°``, ``degrees as radians``.
        kind: ``tolerances``, ``coarse``, ``flip``, ``degrees``, ``half-turn``.
        changed: The numbers it changes, as the check names them.
        model: The wrong table.
    """

    label: str
    kind: str
    changed: tuple[str, ...]
    model: Model


_PARAMS = ("a", "alpha", "d", "theta")
_COMPONENTS = ("x", "y", "z", "rx", "ry", "rz")


def _with_row(model: Model, i: int, **change: Any) -> Model:
    joints = list(model.joints)
    joints[i] = replace(joints[i], **change)
    return replace(model, joints=tuple(joints))


def _with_offset(model: Model, which: str, component: int, delta: float) -> Model:
    offset: Offset = getattr(model, which)
    xyz, rpy = list(offset.xyz), list(offset.rpy)
    (xyz if component < 3 else rpy)[component % 3] += delta
    return replace(model, **{which: Offset(tuple(xyz), tuple(rpy))})  # type: ignore[arg-type]


def faults(model: Model) -> list[Fault]:
    """Every single-number fault, each joint reversed, degrees as radians, half turns."""
    tol = {"m": DEFAULT_TOL_POS_M, "rad": DEFAULT_TOL_ROT_RAD}
    out: list[Fault] = []
    sizes = (
        ("tolerances", lambda u: TOLERANCES * tol[u], lambda u: f"+{TOLERANCES:g} tol"),
        ("coarse", lambda u: COARSE[u], lambda u: "+1 mm" if u == "m" else "+0.001 rad"),
    )
    for kind, size, said in sizes:
        for i, joint in enumerate(model.joints):
            for param in _PARAMS:
                unit = "m" if param in ("a", "d") else "rad"
                name = param_symbol(model, i, param)
                wrong = _with_row(model, i, **{param: getattr(joint, param) + size(unit)})
                out.append(Fault(f"{name} {said(unit)}", kind, (name,), wrong))
        for which in ("base", "tool"):
            if getattr(model, which).is_identity:
                continue
            for c, comp in enumerate(_COMPONENTS):
                unit = "m" if c < 3 else "rad"
                name = f"[{which}] {comp}"
                out.append(Fault(f"{name} {said(unit)}", kind, (name,),
                                 _with_offset(model, which, c, size(unit))))  # fmt: skip
    for i, joint in enumerate(model.joints):
        out.append(Fault(f"flip{i + 1}", "flip", (f"flip{i + 1}",),
                         _with_row(model, i, flip=not joint.flip)))  # fmt: skip
    out.append(_degrees_as_radians(model))
    n = model.dof - 1
    halves = [(0, "theta"), (n, "theta"), (n, "alpha")]
    if model.convention == "modified":
        halves.append((0, "alpha"))
    for i, param in halves:
        name = param_symbol(model, i, param)
        wrong = _with_row(model, i, **{param: getattr(model.joints[i], param) + math.pi})
        out.append(Fault(f"{name} +180°", "half-turn", (name,), wrong))
    if not model.tool.is_identity:
        for c in (3, 5):
            name = f"[tool] {_COMPONENTS[c]}"
            out.append(Fault(f"{name} +180°", "half-turn", (name,),
                             _with_offset(model, "tool", c, math.pi)))  # fmt: skip
    return out


def _degrees_as_radians(model: Model) -> Fault:
    """The table's angles in degrees, read as radians (a file without ``angle_unit``)."""

    def turned(value: float) -> float:
        return math.degrees(value)

    def moved(before: float, after: float) -> bool:
        return abs(math.remainder(after - before, math.tau)) > DEFAULT_TOL_ROT_RAD

    changed: list[str] = []
    joints = []
    for i, j in enumerate(model.joints):
        joints.append(replace(
            j, alpha=turned(j.alpha), theta=turned(j.theta),
            limits=None if j.limits is None else (turned(j.limits[0]), turned(j.limits[1])),
        ))  # fmt: skip
        changed += [param_symbol(model, i, p) for p in ("alpha", "theta")
                    if moved(getattr(j, p), turned(getattr(j, p)))]  # fmt: skip
    wrong = replace(model, joints=tuple(joints))
    for which in ("base", "tool"):
        offset: Offset = getattr(model, which)
        rpy = tuple(turned(v) for v in offset.rpy)
        changed += [f"[{which}] {_COMPONENTS[3 + k]}" for k in range(3)
                    if moved(offset.rpy[k], rpy[k])]  # fmt: skip
        wrong = replace(wrong, **{which: Offset(offset.xyz, rpy)})  # type: ignore[arg-type]
    return Fault("degrees as radians", "degrees", tuple(changed), wrong)


def _fkcheck(argv: Sequence[str]) -> tuple[int, str]:
    """Run the fkcheck command line in this process: exit code, what it printed."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = fkcheck_main(list(argv))
    return code, out.getvalue()


def table_text(model: Model) -> str:
    """The model file as a user writes it: the table, no ``[check]`` (the map's block has one)."""
    return model_to_toml(model).split("\n[check]\n")[0]


def workflow(
    table: str, urdf: str, directory: Path, *, samples: int, seed: int, against: str
) -> dict[str, Any]:
    """``fkcheck map`` the table onto the URDF, paste the block, ``check --require table``."""
    model_file, block_file, report = (directory / n for n in ("arm.toml", "block.toml", "r.json"))
    model_file.write_text(table, encoding="utf-8")
    report.unlink(missing_ok=True)
    code, printed = _fkcheck(["map", str(model_file), urdf, "-o", str(block_file)])
    run: dict[str, Any] = {"map_exit": code, "map": printed.strip().splitlines()}
    if code != 0:
        return run
    model_file.write_text(table + "\n" + block_file.read_text(encoding="utf-8"), encoding="utf-8")
    code, printed = _fkcheck(["check", str(model_file), "--against", against,
                              "--samples", str(samples), "--seed", str(seed), "--require", "table",
                              "--no-diagnose", "--json", str(report)])  # fmt: skip
    run["check_exit"] = code
    if not report.exists():
        run["check"] = printed.strip().splitlines()[-3:]
        return run
    result = json.loads(report.read_text(encoding="utf-8"))
    run.update(
        pair=[result["from"], result["to"]],
        verdict=result["verdict"],
        headline=result["headline"],
        table=result["evidence"]["table"]["status"],
        gaps=result["evidence"]["table"]["gaps"],
        numbers={
            n["name"]: {k: n[k] for k in ("status", "absorbed_by", "competing")}
            for n in result["numbers"]["numbers"]
            if n["table"]
        },
    )
    return run


def classify_fault(run: dict[str, Any], changed: Sequence[str]) -> str:
    """``caught``, ``not-identifiable``, ``not-covered``, ``false-green`` or ``error``."""
    if run["map_exit"] != 0:
        return "caught" if run["map_exit"] == 1 else "error"
    if "verdict" not in run:
        return "error"
    if run["verdict"] == "fail":
        return "caught"
    statuses = [run["numbers"].get(name, {}).get("status", "missing") for name in changed]
    if run["table"] == "verified" or "verified" in statuses or "missing" in statuses:
        return "false-green"
    if "not-identifiable" in statuses:
        return "not-identifiable"
    return "not-covered"


def classify_table(run: dict[str, Any]) -> str:
    """The published table: ``verified``, ``link-only``, ``not-covered`` or ``false-alarm``.

    ``link-only``: every number not verified is not identifiable because another
    link of the description could be the DH frame (named in ``competing``);
    ``not-covered``: besides those, some are outside the pair ``map`` proposed.
    """
    if run["map_exit"] != 0 or "verdict" not in run or run["verdict"] == "fail":
        return "false-alarm"
    left = {k: v for k, v in run["numbers"].items() if v["status"] != "verified"}
    if not left:
        return "verified"
    if any(v["status"] == "not-identifiable" and not v["competing"] for v in left.values()):
        return "false-alarm"
    if any(v["status"] not in ("not-identifiable", "not-covered") for v in left.values()):
        return "false-alarm"
    uncovered = any(v["status"] == "not-covered" for v in left.values())
    return "not-covered" if uncovered else "link-only"


def campaign(
    arms: Sequence[str],
    directory: Path,
    *,
    samples: int = 32,
    seed: int = 0,
    against: str = "pinocchio-urdf",
    pick: Callable[[list[Fault]], list[Fault]] | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict[str, Any]:
    """Run the campaign: each arm's published table, then its faults (those ``pick`` keeps)."""
    out: dict[str, Any] = {"samples": samples, "seed": seed, "against": against, "arms": {}}
    for name in arms:
        arm = ARMS[name]
        where = directory / name
        where.mkdir(parents=True, exist_ok=True)
        urdf = arm.urdf(where)
        (where / "table.toml").write_text(arm.table, encoding="utf-8")
        model = load_model(where / "table.toml")
        chosen = faults(model)
        if pick is not None:
            chosen = pick(chosen)

        def go(text: str, where: Path = where, urdf: str = urdf) -> dict[str, Any]:
            return workflow(text, urdf, where, samples=samples, seed=seed, against=against)

        start = time.perf_counter()
        published = go(table_text(model))
        published["outcome"] = classify_table(published)
        cases = []
        for fault in chosen:
            run = go(table_text(fault.model))
            run.update(label=fault.label, kind=fault.kind, changed=list(fault.changed))
            run["outcome"] = classify_fault(run, fault.changed)
            cases.append(run)
            if progress is not None:
                progress(f"{name}: {fault.label}: {run['outcome']}")
        out["arms"][name] = {
            "vendor": arm.vendor,
            "published": published,
            "faults": cases,
            "counts": dict(Counter(c["outcome"] for c in cases)),
            "seconds": round(time.perf_counter() - start, 1),
        }
    return out


OUTCOMES = ("caught", "not-identifiable", "not-covered", "false-green", "error")


def seeded_subset(size: int, seed: int) -> Callable[[list[Fault]], list[Fault]]:
    """Keep ``size`` faults of each arm, drawn with ``seed``."""

    def pick(faults: list[Fault]) -> list[Fault]:
        return random.Random(seed).sample(faults, min(size, len(faults)))

    return pick


def table_of_counts(result: dict[str, Any]) -> str:
    """One line per arm: the published table's outcome, then the faults' counts."""
    head = f"{'arm':8} {'vendor':17} {'published':12} {'faults':>6} " + " ".join(
        f"{o:>16}" for o in OUTCOMES
    )
    lines = [head]
    for name, arm in result["arms"].items():
        counts = arm["counts"]
        lines.append(
            f"{name:8} {arm['vendor']:17} {arm['published']['outcome']:12} "
            f"{len(arm['faults']):>6} " + " ".join(f"{counts.get(o, 0):>16}" for o in OUTCOMES)
        )
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, default=None, help="write every run here")
    parser.add_argument("--arms", default=",".join(ARMS), help=f"of {', '.join(ARMS)}")
    parser.add_argument("--samples", type=int, default=32)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--against", default="pinocchio-urdf")
    parser.add_argument("--subset", type=int, default=None, help="faults per arm (seeded)")
    parser.add_argument("-v", "--verbose", action="store_true", help="print each outcome")
    args = parser.parse_args(argv)
    arms = [a for a in args.arms.split(",") if a]
    unknown = [a for a in arms if a not in ARMS]
    if unknown:
        print(f"verdict_campaign: unknown arm {', '.join(unknown)}: use {', '.join(ARMS)}",
              file=sys.stderr)  # fmt: skip
        return 2
    progress = (lambda line: print(line, flush=True)) if args.verbose else None
    pick = None if args.subset is None else seeded_subset(args.subset, args.seed)
    with tempfile.TemporaryDirectory(prefix="verdict-campaign-") as tmp:
        result = campaign(arms, Path(tmp), samples=args.samples, seed=args.seed,
                          against=args.against, progress=progress,
                          pick=pick)  # fmt: skip
    if args.json is not None:
        args.json.write_text(json.dumps(result, indent=1, ensure_ascii=False) + "\n",
                             encoding="utf-8")  # fmt: skip
    print(table_of_counts(result))
    bad = [
        f"{name}: {c['label']}: {c['outcome']}: {c.get('headline', c['map'][0])}"
        for name, arm in result["arms"].items()
        for c in arm["faults"]
        if c["outcome"] in ("false-green", "error")
    ] + [
        f"{name}: the published table: {p.get('headline', p['map'][0])}"
        for name, arm in result["arms"].items()
        if (p := arm["published"])["outcome"] == "false-alarm"
    ]
    for line in bad:
        print(line)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
