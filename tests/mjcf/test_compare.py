"""Two readers of one MJCF compared; Pinocchio 4.1.0's measured MJCF bugs, each named.

None of them may end in a traceback or a silent pass: the reader raises a
ReaderError (a result of the comparison), or the comparison names the reader
with its version.
"""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import numpy as np
import pinocchio
import pytest

from fkcheck.errors import FrameError, JointInputError, MjcfError
from fkcheck.mjcf import compare_readers, mujoco_poses, pinocchio_poses, read_mjcf, readers
from fkcheck.model.read import bundled_models_dir, load_model
from tests.mjcf.hand import T, deg, rot, rz, tr

PIN_410 = pinocchio.__version__ == "4.1.0"
EXACT = 1e-12
I4 = np.eye(4)
Q = np.array([[0.7, -0.4], [-1.2, 2.0], [3.0, 0.1]])

ROOTED = """<mujoco model="rooted">
  <compiler {compiler}/>
  {top}
  <worldbody>
    <body name="base" {base}>
      <body name="b1" pos="0 0 0.3">
        <joint name="j1" axis="0 0 1"/>
        <body name="b2" pos="0.4 0 0" {b2}>
          <joint name="j2" {j2}/>
          <site name="tip" pos="0.25 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def rooted(tmp_path: Path, *, compiler="", top="", base="", b2="", j2='axis="0 1 0"') -> Path:
    path = tmp_path / "rooted.xml"
    path.write_text(ROOTED.format(compiler=compiler, top=top, base=base, b2=b2, j2=j2))
    return path


def hand(q: np.ndarray, base=I4, b2=I4, axis=(0, 1, 0)) -> np.ndarray:
    return np.stack(
        [
            T(base, tr(0, 0, 0.3), rz(a), tr(0.4, 0, 0), b2, rot(axis, b), tr(0.25, 0, 0))
            for a, b in q
        ]
    )[None]


def test_jointless_root_body_turned_pinocchio_2782(tmp_path: Path) -> None:
    """A root body without a joint, turned π about z: Pinocchio 4.1.0 drops its placement."""
    path = rooted(tmp_path, base='pos="0.5 0 0" quat="0 0 0 1"')
    expected = hand(Q, base=T(tr(0.5, 0, 0), rz(np.pi)))
    desc = read_mjcf(path)
    np.testing.assert_allclose(mujoco_poses(desc, ["tip"], Q), expected, atol=EXACT)
    held = compare_readers(desc, ["tip"], Q, reference=("the hand pose", expected))
    if PIN_410:
        assert held.disagreeing == ("pinocchio-mjcf",)
        pin = held.results[1]
        assert pin.version == "Pinocchio 4.1.0"
        assert pin.rotation_rad == pytest.approx(np.pi, abs=1e-9)
        assert "pinocchio-mjcf (Pinocchio 4.1.0): DISAGREES" in held.summary()
    else:
        assert "mujoco-mjcf" not in held.disagreeing


def test_without_a_reference_both_readers_are_named(tmp_path: Path) -> None:
    desc = read_mjcf(rooted(tmp_path, base='quat="0 0 0 1"'))
    held = compare_readers(desc, ["tip"], Q)
    assert held.reference is None
    if PIN_410:
        assert held.disagreeing == ("mujoco-mjcf", "pinocchio-mjcf")
        assert not held.agree
        assert "readers held to each other" in held.summary()


def test_included_defaults_crash_pinocchio_but_never_reach_it(tmp_path: Path) -> None:
    (tmp_path / "defaults.xml").write_text(
        '<mujoco><default><default class="arm"><joint axis="1 0 0"/></default></default></mujoco>'
    )
    path = rooted(tmp_path, top='<include file="defaults.xml"/>', j2='class="arm"')
    if PIN_410:  # the bug itself, on the file as written (Pinocchio resolving the include)
        with pytest.raises(IndexError, match="unordered_map::at"):
            pinocchio.buildModelFromMJCF(str(path))
    desc = read_mjcf(path)  # the screen inlines the include: Pinocchio never sees it
    expected = hand(Q, axis=(1, 0, 0))
    held = compare_readers(
        desc, ["tip"], Q, reference=("the hand pose", expected), tol_pos_m=EXACT, tol_rot_rad=EXACT
    )
    assert held.agree, held.summary()


def test_eulerseq_XYZ_with_an_unnormalised_axisangle(tmp_path: Path) -> None:
    """MuJoCo normalises the axis; Pinocchio 4.1.0 builds a matrix that is no rotation."""
    path = rooted(tmp_path, compiler='eulerseq="XYZ"', b2='axisangle="1 2 3 30"')
    expected = hand(Q, b2=rot((1, 2, 3), deg(30)))
    desc = read_mjcf(path)
    np.testing.assert_allclose(mujoco_poses(desc, ["tip"], Q), expected, atol=EXACT)
    held = compare_readers(desc, ["tip"], Q, reference=("the hand pose", expected))
    if PIN_410:
        assert held.disagreeing == ("pinocchio-mjcf",)
        assert held.results[1].position_m > 0.1  # decimetres to metres off
    else:
        assert "mujoco-mjcf" not in held.disagreeing


def test_a_failing_reader_is_a_result_not_a_traceback(tmp_path: Path) -> None:
    path = tmp_path / "framed.xml"
    path.write_text(
        '<mujoco><worldbody><frame pos="0 0 1"><body name="b"><joint name="j"/>'
        '<site name="s"/></body></frame></worldbody></mujoco>'
    )
    desc = read_mjcf(path)
    held = compare_readers(desc, ["s"], [[0.3]])
    if PIN_410:  # its parser does not read <frame>: a worldbody holding only one fails it
        message = "cannot read it: RuntimeError: No such node (body)"
        with pytest.raises(
            readers.ReaderError,
            match=r"pinocchio-mjcf \(Pinocchio 4\.1\.0\) "
            r"failed: cannot read it: RuntimeError",
        ):
            pinocchio_poses(desc, ["s"], [[0.3]])
        assert held.results[1].error == message
        assert held.disagreeing == ("pinocchio-mjcf",)
        assert f"failed: {message}" in held.summary()


def test_a_library_exception_is_kept_with_its_type(tmp_path: Path) -> None:
    desc = read_mjcf(rooted(tmp_path))

    def broken(*_args: object, **_kwargs: object) -> np.ndarray:
        raise RuntimeError("segment table full")

    held = compare_readers(
        desc, ["tip"], Q, readers={"mujoco-mjcf": mujoco_poses, "broken": broken}
    )
    assert held.results[1].error == "RuntimeError: segment table full"
    assert held.results[1].version == "version unknown"
    assert held.disagreeing == ("broken",)


def test_bad_input_is_no_readers_fault(tmp_path: Path) -> None:
    desc = read_mjcf(rooted(tmp_path))
    with pytest.raises(
        FrameError,
        match=r"frame 'flange' not in MJCF rooted\.xml; frames are: world, base, b1, b2, tip",
    ):
        compare_readers(desc, ["flange"], Q)
    with pytest.raises(
        MjcfError, match="'j9' is not a hinge or slide joint; its joints are: j1, j2"
    ):
        compare_readers(desc, ["tip"], Q[:, :1], joints=["j9"])
    with pytest.raises(JointInputError, match=r"shape \(N, 2\)"):
        mujoco_poses(desc, ["tip"], [[1.0, 2.0, 3.0]])
    with pytest.raises(JointInputError, match="finite"):
        pinocchio_poses(desc, ["tip"], [[np.nan, 0.0]])


def test_readers_read_the_text_not_fkcheck_s_tree() -> None:
    """The readers touch the description's text, names and qpos0 only (never .kinematics)."""
    tree = ast.parse(inspect.getsource(readers))
    touched = {
        n.attr
        for n in ast.walk(tree)
        if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name) and n.value.id == "desc"
    }
    assert touched == {"text", "path", "joints", "frames", "bodies", "qpos0"}
    imported = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert not imported & {"fkcheck.urdf.chain", "fkcheck.core.dh", "fkcheck.core.geometry"}


# --- seeded faults in a right MJCF: both readers must see each one -----------------------

PANDA = bundled_models_dir() / "mujoco_menagerie" / "franka_emika_panda" / "panda_nohand.xml"
FAULTS = {
    "an angle unit": (
        '<compiler angle="radian" autolimits="true"/>',
        '<compiler autolimits="true"/>',
    ),
    "a ref": ('<joint name="joint3"/>', '<joint name="joint3" ref="0.1"/>'),
    "an axis sign": ('<joint name="joint4" range', '<joint name="joint4" axis="0 0 -1" range'),
    "a body 1 mm off": ('pos="0 -0.316 0"', 'pos="0 -0.317 0"'),
    "a class default": ('damping="1" axis="0 0 1"', 'damping="1" axis="0 0.01 1"'),
}


@pytest.mark.parametrize("fault", sorted(FAULTS))
def test_seeded_fault_fails_in_both_readers(tmp_path: Path, fault: str) -> None:
    right, wrong = FAULTS[fault]
    text = PANDA.read_text()
    # The angle unit shows only where an angle is written: link2's quarter turn as euler.
    text = text.replace(
        '<body name="link2" quat="1 -1 0 0">', '<body name="link2" euler="-1.5707963267948966 0 0">'
    )
    assert text.count(right) == 1
    model = load_model("panda")
    rng = np.random.default_rng(3)
    q = rng.uniform(-1.5, -0.1, (100, 7))
    frames = [f"link{i}" for i in range(1, 8)]
    reference = ("the Panda's DH table", np.moveaxis(model.fk(q, all_frames=True)[:, 1:], 1, 0))
    (tmp_path / "right.xml").write_text(text)
    assert compare_readers(
        read_mjcf(tmp_path / "right.xml"),
        frames,
        q,
        reference=reference,
        tol_pos_m=1e-9,
        tol_rot_rad=1e-9,
    ).agree
    (tmp_path / "wrong.xml").write_text(text.replace(right, wrong))
    held = compare_readers(read_mjcf(tmp_path / "wrong.xml"), frames, q, reference=reference)
    assert held.disagreeing == ("mujoco-mjcf", "pinocchio-mjcf"), held.summary()
    assert all(r.error is None and r.position_m > 5e-4 for r in held.results)
