"""A subset compared, all numbers claimed (issue 30, item 2).

A table backend over its budget compares the structured configurations first
(:mod:`fkcheck.engine.plan`). On an arm whose limits are ±2π those are all
``q ≡ 0 (mod 2π)``: one pose, which cannot tell a joint's direction nor a
split of a2/a3. The numbers' evidence must come from what the table's evidence
answered, not from every configuration of the check.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from fkcheck.backends.registry import make_backend
from fkcheck.engine.runner import run_check
from fkcheck.engine.verdict import headline
from fkcheck.model.read import load_model

#: UR5e's nominal DH table (standard): a (m), α (rad), d (m); θ offsets 0.
UR5E = (
    (0.0, math.pi / 2, 0.1625),
    (-0.425, 0.0, 0.0),
    (-0.3922, 0.0, 0.0),
    (0.0, math.pi / 2, 0.1333),
    (0.0, -math.pi / 2, 0.0997),
    (0.0, 0.0, 0.0996),
)
#: A cost no budget fits: the plan gives the backend its structured configurations only.
PRICELESS_US = 1e9


def _urdf(rows: tuple[tuple[float, float, float], ...], axes: tuple[int, ...]) -> str:
    """A URDF whose links are the DH frames: joint i+1 sits at Tz(d_i)·Tx(a_i)·Rx(α_i)."""
    out = ['<robot name="arm">', '<link name="base"/>']
    parent, origin = "base", (0.0, 0.0, 0.0)
    for i, (a, alpha, d) in enumerate(rows):
        out.append(f'<link name="l{i + 1}"/>')
        out.append(
            f'<joint name="j{i + 1}" type="revolute"><parent link="{parent}"/>'
            f'<child link="l{i + 1}"/><origin xyz="{origin[0]!r} 0 {origin[2]!r}" '
            f'rpy="{origin[1]!r} 0 0"/><axis xyz="0 0 {axes[i]}"/>'
            '<limit lower="-6.283185307179586" upper="6.283185307179586" effort="1" '
            'velocity="1"/></joint>'
        )
        parent, origin = f"l{i + 1}", (a, alpha, d)
    out.append('<link name="tool0"/>')
    out.append(
        f'<joint name="flange" type="fixed"><parent link="{parent}"/><child link="tool0"/>'
        f'<origin xyz="{origin[0]!r} 0 {origin[2]!r}" rpy="{origin[1]!r} 0 0"/></joint>'
    )
    return "\n".join([*out, "</robot>"])


def _model(tmp_path: Path, urdf: str) -> Path:
    """UR5e's table (no named poses: structured = zero, mid, corners, edges) and ``urdf``."""
    (tmp_path / "arm.urdf").write_text(urdf, encoding="utf-8")
    joints = "".join(
        f'[[joint]]\nname = "j{i + 1}"\na = {a!r}\nalpha = {math.degrees(al)!r}\nd = {d!r}\n'
        "theta = 0\nlimits = [-360.0, 360.0]\n\n"
        for i, (a, al, d) in enumerate(UR5E)
    )
    path = tmp_path / "arm.toml"
    path.write_text(
        'name = "arm"\nconvention = "standard"\nangle_unit = "deg"\n\n'
        f"{joints}"
        '[urdf]\npath = "arm.urdf"\njoints = ["j1", "j2", "j3", "j4", "j5", "j6"]\n\n'
        '[frames.base]\ndh = 0\nurdf = "base"\n\n[frames.tool0]\ndh = 6\nurdf = "tool0"\n\n'
        '[check]\nfrom = "base"\nto = "tool0"\n',
        encoding="utf-8",
    )
    return path


def _wrong(kind: str) -> str:
    rows = list(UR5E)
    axes = [1] * 6
    if kind == "joint 2 reversed":
        axes[1] = -1
    else:  # a2/a3 split 50 mm differently, the same sum
        rows[1], rows[2] = (-0.375, 0.0, 0.0), (-0.4422, 0.0, 0.0)
    return _urdf(tuple(rows), tuple(axes))


def _check(model: Path, *, subset: bool, names: tuple[str, ...] = ("pinocchio-urdf",)):
    backends = [make_backend(n) for n in names]
    if subset:
        backends[0].pose_cost_us = PRICELESS_US  # type: ignore[misc]
    return run_check(load_model(model), backends, samples=200, seed=0, require=("table",))


WRONG = ["joint 2 reversed", "a2/a3 split"]


@pytest.mark.parametrize("kind", WRONG)
def test_the_wrong_urdf_fails_on_every_configuration(tmp_path, kind):
    """The URDFs below are wrong: compared on all the check's configurations, they fail."""
    result = _check(_model(tmp_path, _wrong(kind)), subset=False)
    assert result.verdict == "fail"


@pytest.mark.parametrize("kind", WRONG)
def test_a_subset_at_one_pose_verifies_no_number(tmp_path, kind):
    result = _check(_model(tmp_path, _wrong(kind)), subset=True)
    (only,) = result.backends
    assert only.status == "pass"
    assert only.subset == (78, 278)  # zero, mid, 64 corners, 12 edges: all q ≡ 0 mod 2π
    assert result.numbers is not None
    by_name = {n.name: n for n in result.numbers.table_numbers}
    # What the wrong URDF hides is not verified, and says why.
    for name in ("flip2", "a2", "a3"):
        assert by_name[name].status == "not-identifiable", name
    assert by_name["flip2"].reason == "direction"
    assert by_name["a2"].reason == "configurations"
    assert "78 configurations" in by_name["a2"].absorbed_by
    line = headline(result.verdict, result.evidence, len(result.ran))
    assert "table verified" not in line
    assert result.verdict == "unverified"  # --require table: not a pass
    assert result.evidence.table.status == "partly-verified"


def test_the_numbers_come_from_the_backend_that_compared_most(tmp_path):
    """Two table backends, one on a subset: the full one's configurations verify the table."""
    right = _urdf(UR5E, (1,) * 6)
    result = _check(_model(tmp_path, right), subset=True,
                    names=("pinocchio-urdf", "rtb-urdf"))  # fmt: skip
    assert [b.subset for b in result.backends] == [(78, 278), None]
    assert result.verdict == "pass"
    assert result.numbers is not None
    assert result.numbers.complete
    assert headline(result.verdict, result.evidence, 2).startswith(
        "pass — table verified independently"
    )


def test_the_right_urdf_on_a_subset_with_random_samples_is_verified(tmp_path):
    """A subset whose random prefix moves every joint verifies every number."""
    model = _model(tmp_path, _urdf(UR5E, (1,) * 6))
    backend = make_backend("pinocchio-urdf")
    # 60 s of budget at 0.5 s a configuration: the 78 structured ones and 42 random samples.
    backend.pose_cost_us = 5e5  # type: ignore[misc]
    result = run_check(load_model(model), [backend], samples=200, seed=0, require=("table",))
    assert result.backends[0].subset == (120, 278)
    assert result.verdict == "pass"
    assert result.numbers is not None
    assert result.numbers.complete
