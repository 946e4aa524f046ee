"""The iDynTree backend: the reference URDF through iDynTree's parser, and the traps it avoids.

Each trap the module docstring of :mod:`fkcheck.backends.idyntree_urdf` names
has a test here that fails without its handling: links kept as frames, the
URDF root not a link, the reduced model's joint order, meshes, mimic joints,
floating-base Jacobian columns, and temporaries read after they are freed.
"""

from __future__ import annotations

import ast
import inspect
import subprocess
import sys

import numpy as np
import pytest

from fkcheck.backends import idyntree_urdf, registry
from fkcheck.backends.base import BackendUnavailable, SharesDHFrames
from fkcheck.backends.idyntree_urdf import IdyntreeUrdf
from fkcheck.backends.pinocchio_urdf import PinocchioUrdf
from fkcheck.backends.registry import make_backend
from fkcheck.backends.urdf_common import kinematic_text
from fkcheck.cli.main import main
from fkcheck.core.tolerances import ROUNDED_URDF, SAME_CHAIN
from fkcheck.core.typing import JACOBIAN_REFERENCES
from fkcheck.engine.runner import run_check
from fkcheck.errors import UnmappedFrameError, UrdfError
from fkcheck.model.read import load_model
from fkcheck.model.types import Model
from fkcheck.urdf.source import load_urdf
from tests.backend_cases import (
    ARM3_TOML,
    ARM3_URDF,
    URDF_MODELS,
    arm3_model,
    assert_every_pair_agrees,
    edited_ur5_ros1,
    mapped_frames,
    pair_errors,
)
from tests.helpers import assert_pose_close, random_q, ur5_ros1

idt = pytest.importorskip("idyntree.bindings")

#: Bundled models whose URDF differs from their table (recorded): compared with Pinocchio's reading.
RECORDED_MODELS = ["baxter_left", "baxter_right", "jaco2_6s", "xarm7"]


@pytest.fixture(scope="module")
def backend() -> IdyntreeUrdf:
    return IdyntreeUrdf()


@pytest.fixture(scope="module")
def pinocchio() -> PinocchioUrdf:
    pytest.importorskip("pinocchio")
    return PinocchioUrdf()


def full_model(model: Model) -> tuple[object, object]:
    """iDynTree's full (not reduced) model of the model's geometry-free URDF, and its loader."""
    loader = idt.ModelLoader()
    assert loader.loadModelFromString(kinematic_text(load_urdf(model)))
    return loader, loader.model()  # the model is a reference into the loader: keep both


def gripper_model(tmp_path, offset: float) -> Model:
    """arm3 with two unmapped fingers on ``l3``, the second mimicking the first (+ ``offset``)."""
    fingers = f"""
  <link name="finger1"/>
  <link name="finger2"/>
  <joint name="f1" type="prismatic">
    <parent link="l3"/><child link="finger1"/>
    <origin xyz="0 0.02 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" effort="1" velocity="1"/>
  </joint>
  <joint name="f2" type="prismatic">
    <parent link="l3"/><child link="finger2"/>
    <origin xyz="0 -0.02 0" rpy="0 0 0"/><axis xyz="0 -1 0"/>
    <limit lower="0" upper="0.04" effort="1" velocity="1"/>
    <mimic joint="f1" multiplier="1" offset="{offset}"/>
  </joint>
</robot>"""
    tmp_path.mkdir(exist_ok=True)
    (tmp_path / "arm3.urdf").write_text(ARM3_URDF.replace("</robot>", fingers))
    (tmp_path / "arm3.toml").write_text(
        ARM3_TOML + '\n[frames.finger2]\ndh = 3\nxyz = [0.0, -0.02, 0.0]\nurdf = "finger2"\n'
    )
    return load_model(tmp_path / "arm3.toml")


# ---------------------------------------------------------------- registry, availability


def test_registry_builds_it_as_a_default_urdf_reader() -> None:
    # The contract itself is the conformance suite's (tests/backends/test_conformance.py).
    backend = make_backend("idyntree-urdf")
    assert isinstance(backend, IdyntreeUrdf)
    assert not isinstance(backend, SharesDHFrames)
    assert (backend.evidence, backend.reads, backend.isolated) == ("table", "urdf", False)
    assert backend.imports[0] == "fkcheck.backends._idyntree"  # never idyntree first
    assert backend.jacobian_method is not None
    assert "getFrameFreeFloatingJacobian" in backend.jacobian_method
    assert set(backend.jacobian_references) == set(JACOBIAN_REFERENCES)
    assert registry.default_names()[-1] == "idyntree-urdf"
    assert "idyntree-urdf" in registry.names(reads="urdf")
    assert "idyntree-urdf" in registry.known_difference_names()


def test_it_runs_where_warnings_are_errors() -> None:
    # The trap: SWIG's import-time DeprecationWarning, made an error, is a segmentation
    # fault while idyntree.bindings initialises (pytest's filterwarnings = ["error"] too).
    raw = subprocess.run(
        [sys.executable, "-W", "error", "-c", "import idyntree.bindings"],
        capture_output=True,
        timeout=120,
    )
    assert raw.returncode != 0
    code = (
        "from fkcheck.cli.main import main\n"
        "raise SystemExit(main(['check', 'ur5', '--samples', '10', '--against', "
        "'idyntree-urdf', '--jacobian']))\n"
    )
    run = subprocess.run(
        [sys.executable, "-W", "error", "-c", code], capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "verdict: pass" in run.stdout


def test_a_model_without_urdf_is_unavailable(backend: IdyntreeUrdf) -> None:
    planar = load_model("planar2")
    assert backend.unavailable_reason(planar) == "model has no [urdf]"
    assert backend.inputs(planar) == ()
    with pytest.raises(BackendUnavailable, match=r"model has no \[urdf\]"):
        backend.frame_poses(planar, np.zeros((1, 2)), ["tcp"])


def test_missing_idyntree_is_reported_with_the_install_command(
    backend: IdyntreeUrdf, monkeypatch: pytest.MonkeyPatch
) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "idyntree" else real(name)
    )
    reason = backend.unavailable_reason(load_model("ur5"))
    assert reason == "idyntree is not installed (pip install 'fkcheck[reference]')"


def test_its_input_is_the_models_urdf(backend: IdyntreeUrdf) -> None:
    ur5 = load_model("ur5")
    assert backend.inputs(ur5) == (load_urdf(ur5).path,)
    assert backend.inputs(ur5)[0].name == "ur.urdf.xacro"  # UR's ROS 2 description, bundled


# ---------------------------------------------------------------- against the core


def test_continuous_flipped_and_prismatic_joints(
    backend: IdyntreeUrdf, tmp_path, rng: np.random.Generator
) -> None:
    model = arm3_model(tmp_path)
    q = random_q(model, rng, 50)
    frames = mapped_frames(model)
    assert_every_pair_agrees(model, q, frames, backend.frame_poses(model, q, frames), SAME_CHAIN)


@pytest.mark.parametrize("reference", JACOBIAN_REFERENCES)
@pytest.mark.parametrize("name", URDF_MODELS)
def test_jacobians_agree_with_core_in_every_reference(name: str, reference: str) -> None:
    check = run_check(
        load_model(name),
        [make_backend("idyntree-urdf")],
        samples=20,
        seed=5,
        jacobian=True,
        jacobian_reference=reference,
        tol_jacobian=1e-6,  # type: ignore[arg-type]
    )
    assert check.verdict == "pass", [(b.name, b.message, b.jacobian) for b in check.backends]
    (result,) = check.backends
    assert result.jacobian is not None
    assert "getFrameFreeFloatingJacobian" in result.jacobian.method  # its own, not differences
    assert result.jacobian.max_linear_error < ROUNDED_URDF
    assert result.jacobian.max_angular_error < ROUNDED_URDF


def test_a_seeded_urdf_fault_of_0_1_mm_disagrees(
    backend: IdyntreeUrdf, tmp_path, rng: np.random.Generator
) -> None:
    # A copy of UR5's plain ROS 1 URDF (example-robot-data's ur5_robot.urdf; the bundled
    # model reads ROS 2's xacro) with the elbow 0.1 mm further along the upper arm.
    urdf = load_urdf(ur5_ros1()).path.read_text()
    old = '<origin rpy="0.0 0.0 0.0" xyz="0.0 -0.1197 0.425"/>'
    assert urdf.count(old) == 1
    (tmp_path / "ur5_seeded.urdf").write_text(urdf.replace(old, old.replace("0.425", "0.4251")))
    erd = 'path = "example-robot-data:ur_description/urdf/ur5_robot.urdf"'
    model = load_model(edited_ur5_ros1(tmp_path, erd, 'path = "ur5_seeded.urdf"'))
    q = random_q(model, rng, 50)
    pos, _ = pair_errors(
        model, q, "base", "tool0", backend.frame_poses(model, q, ["base", "tool0"])
    )
    assert 1e-5 < pos.max() <= 1.0001e-4
    check = run_check(model, [backend], samples=20, seed=1)
    assert check.verdict == "fail"


def test_check_against_idyntree_passes_from_the_command_line(capsys) -> None:
    code = main(["check", "ur5", "--samples", "200", "--against", "idyntree-urdf"])
    out = "".join(capsys.readouterr())
    assert code == 0, out
    assert "idyntree-urdf" in out
    assert "verdict: pass" in out


def test_check_with_its_jacobian_passes_from_the_command_line(capsys) -> None:
    for reference in JACOBIAN_REFERENCES:
        argv = ["check", "ur5", "--samples", "50", "--against", "idyntree-urdf"]
        code = main([*argv, "--jacobian-reference", reference])
        out = "".join(capsys.readouterr())
        assert code == 0, out
        assert "verdict: pass" in out


@pytest.mark.parametrize("name", URDF_MODELS + RECORDED_MODELS)
def test_poses_and_jacobians_are_pinocchios_in_the_same_root(
    backend: IdyntreeUrdf, pinocchio: PinocchioUrdf, rng: np.random.Generator, name: str
) -> None:
    # Both read the same URDF into the same root (its root link): absolute poses agree,
    # and the Jacobians agree column by column in each reference.
    model = load_model(name)
    q = random_q(model, rng, 30)
    frames = mapped_frames(model)
    assert_pose_close(
        backend.frame_poses(model, q, frames), pinocchio.frame_poses(model, q, frames), 1e-13, name
    )
    for reference in JACOBIAN_REFERENCES:
        ours = backend.frame_jacobian(model, q, frames[-1], reference)  # type: ignore[arg-type]
        theirs = pinocchio.frame_jacobian(model, q, frames[-1], reference)  # type: ignore[arg-type]
        assert ours.shape == (30, 6, model.dof)
        np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-13, err_msg=reference)


def test_a_urdf_idyntree_cannot_load_leaves_it_unavailable_in_one_line_with_its_reason(
    backend: IdyntreeUrdf, tmp_path
) -> None:
    model = arm3_model(tmp_path)
    text = ARM3_URDF.replace('name="tip_joint" type="fixed"', 'name="tip_joint" type="planar"')
    (tmp_path / "arm3.urdf").write_text(text)
    match = r"^iDynTree cannot load arm3\.urdf: .*Joint tip_joint has type planar that is not "
    with pytest.raises(BackendUnavailable, match=match) as info:
        backend.frame_poses(model, np.zeros((1, 3)), ["base", "l3"])
    assert "\n" not in str(info.value)


def test_frame_without_twin_is_an_unmapped_frame_error(backend: IdyntreeUrdf) -> None:
    ur5 = load_model("ur5")
    with pytest.raises(UnmappedFrameError, match=r"frame 'tcp' \(at the tcp\) has no URDF twin"):
        backend.frame_poses(ur5, np.zeros((1, 6)), ["base", "tcp"])


# ---------------------------------------------------------------- the traps


def test_links_on_fixed_joints_are_found_though_idyntree_keeps_them_as_frames(
    backend: IdyntreeUrdf, rng: np.random.Generator
) -> None:
    ur5 = load_model("ur5")
    _, imodel = full_model(ur5)
    links = {imodel.getLinkName(i) for i in range(imodel.getNrOfLinks())}
    names = ["base_link", "base", "tool0", "flange"]
    assert {"world", "base", "tool0"}.isdisjoint(links)  # the trap: not links
    # ROS 2's flange is on a fixed joint too, but tool0 hangs off it: iDynTree keeps it a link.
    assert {"base_link", "flange"} <= links
    q = random_q(ur5, rng, 20)
    assert_every_pair_agrees(ur5, q, names, backend.frame_poses(ur5, q, names), ROUNDED_URDF)


def test_the_root_is_the_urdf_root_link_even_where_idyntree_keeps_it_as_a_frame(
    backend: IdyntreeUrdf, pinocchio: PinocchioUrdf, tmp_path, rng: np.random.Generator
) -> None:
    # A massless root `world` on a fixed joint, offset and turned, above a `base` with mass:
    # iDynTree's base link is `base`; the poses must still be in `world`, as Pinocchio's are.
    inertial = (
        '<inertial><mass value="1"/>'
        '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>'
    )
    text = ARM3_URDF.replace(
        '<link name="base"/>', f'<link name="world"/><link name="base">{inertial}</link>'
    )
    text = text.replace(
        "</robot>",
        '<joint name="world_joint" type="fixed"><parent link="world"/><child link="base"/>'
        '<origin xyz="0.1 -0.2 0.3" rpy="0.3 -0.2 1.1"/></joint></robot>',
    )
    model = arm3_model(tmp_path)
    (tmp_path / "arm3.urdf").write_text(text)
    assert load_urdf(model).root == "world"
    loader = idt.ModelLoader()
    assert loader.loadModelFromString(text)
    assert loader.model().getLinkName(loader.model().getDefaultBaseLink()) == "base"
    q = random_q(model, rng, 20)
    frames = mapped_frames(model)
    poses = backend.frame_poses(model, q, frames)
    assert_pose_close(poses, pinocchio.frame_poses(model, q, frames), 1e-13)
    jac = backend.frame_jacobian(model, q, "tip", "world")
    np.testing.assert_allclose(
        jac, pinocchio.frame_jacobian(model, q, "tip", "world"), rtol=0, atol=1e-13
    )


@pytest.mark.parametrize("name", ["baxter_left", "baxter_right"])
def test_each_dh_joint_drives_its_own_urdf_joint_though_idyntree_orders_them_otherwise(
    backend: IdyntreeUrdf, pinocchio: PinocchioUrdf, rng: np.random.Generator, name: str
) -> None:
    model = load_model(name)
    assert model.urdf is not None
    _, imodel = full_model(model)
    offsets = [imodel.getJoint(imodel.getJointIndex(j)).getDOFsOffset() for j in model.urdf.joints]
    assert offsets != list(range(model.dof))  # the trap: the arm is not iDynTree's first DOFs
    q = random_q(model, rng, 30)
    frames = mapped_frames(model)
    poses = backend.frame_poses(model, q, frames)
    assert_pose_close(poses, pinocchio.frame_poses(model, q, frames), 1e-13, name)
    # ... and a joint's value moving another joint would show: the DH order reversed.
    wrong = backend.frame_poses(model, q[:, ::-1], frames)
    assert np.abs(wrong - poses).max() > 0.01


def test_meshes_are_never_given_to_idyntree(
    backend: IdyntreeUrdf, tmp_path, rng: np.random.Generator, monkeypatch: pytest.MonkeyPatch
) -> None:
    # arm3's tip has a package://nowhere/tip.stl mesh; iDynTree would keep (and try to
    # resolve) it from the raw text.
    model = arm3_model(tmp_path)
    loader = idt.ModelLoader()
    assert loader.loadModelFromString(load_urdf(model).text)
    shapes = loader.model().visualSolidShapes().getLinkSolidShapes()
    assert sum(len(link) for link in shapes) == 1  # the trap: the raw text carries the mesh
    given: list[str] = []
    real = idt.ModelLoader.loadReducedModelFromString

    def spy(self, text, *args):
        given.append(text)
        return real(self, text, *args)

    monkeypatch.setattr(idt.ModelLoader, "loadReducedModelFromString", spy)
    q = random_q(model, rng, 10)
    assert_every_pair_agrees(
        model, q, mapped_frames(model), backend.frame_poses(model, q, mapped_frames(model)), 1e-12
    )
    assert len(given) == 1
    for word in ("<mesh", "package://", "<visual", "<collision"):
        assert word not in given[0]


def test_a_dh_joint_mapped_onto_a_mimic_joint_is_refused_in_one_line(
    backend: IdyntreeUrdf, tmp_path
) -> None:
    # iDynTree ignores <mimic>: it would move j2 by the DH value, the URDF by j1's.
    text = ARM3_URDF.replace(
        '<axis xyz="0 0 -1"/>', '<axis xyz="0 0 -1"/><mimic joint="j1" multiplier="2"/>'
    )
    model = arm3_model(tmp_path)
    (tmp_path / "arm3.urdf").write_text(text)
    for call in (
        lambda: backend.frame_poses(model, np.zeros((1, 3)), ["base", "tip"]),
        lambda: backend.frame_jacobian(model, np.zeros((1, 3)), "tip", "local"),
    ):
        with pytest.raises(UrdfError, match=r"joint 'j2' mimics 'j1' in the URDF") as info:
            call()
        assert "\n" not in str(info.value)


def test_an_unmapped_mimic_joint_at_rest_is_used_and_one_that_is_not_is_refused(
    backend: IdyntreeUrdf, pinocchio: PinocchioUrdf, tmp_path, rng: np.random.Generator
) -> None:
    # Offset 0 and an unmapped leader at 0: the URDF puts the mimic joint at 0, as iDynTree.
    model = gripper_model(tmp_path / "rest", 0.0)
    q = random_q(model, rng, 10)
    frames = mapped_frames(model)
    assert_pose_close(
        backend.frame_poses(model, q, frames), pinocchio.frame_poses(model, q, frames), 1e-13
    )
    # Offset 0.01: the URDF puts finger2 0.01 m out; iDynTree would leave it at 0.
    model = gripper_model(tmp_path / "offset", 0.01)
    with pytest.raises(
        UrdfError, match=r"link 'finger2' lies below joint 'f2', which mimics 'f1'"
    ) as info:
        backend.frame_poses(model, q, ["base", "finger2"])
    assert "\n" not in str(info.value)
    backend.frame_poses(model, q, ["base", "tip"])  # frames elsewhere are unaffected


def test_the_floating_base_columns_are_dropped(
    backend: IdyntreeUrdf, rng: np.random.Generator
) -> None:
    ur5 = load_model("ur5")
    q = random_q(ur5, rng, 5)
    # The trap: iDynTree's Jacobian has six base columns in front of the joints'.
    loader = idt.ModelLoader()
    assert ur5.urdf is not None
    assert loader.loadReducedModelFromString(kinematic_text(load_urdf(ur5)), list(ur5.urdf.joints))
    kin_dyn = idt.KinDynComputations()
    assert kin_dyn.loadRobotModel(loader.model())
    assert kin_dyn.setFrameVelocityRepresentation(idt.MIXED_REPRESENTATION)
    full = idt.MatrixDynSize(6, 6 + ur5.dof)
    ours = backend.frame_jacobian(ur5, q, "tool0", "world-aligned")
    assert ours.shape == (5, 6, ur5.dof)
    tool0 = kin_dyn.getFrameIndex("tool0")
    for k in range(5):
        joints = idt.VectorDynSize.FromPython(q[k].tolist())
        assert kin_dyn.setJointPos(joints)
        assert kin_dyn.getFrameFreeFloatingJacobian(tool0, full)
        matrix = full.toNumPy()
        assert matrix.shape == (6, 6 + ur5.dof)
        # UR's root `world` coincides with iDynTree's base link `base_link` here.
        np.testing.assert_allclose(ours[k], matrix[:, 6:], rtol=0, atol=1e-15)
        # The base's: its linear velocity moves the frame's origin one for one (MIXED).
        np.testing.assert_allclose(matrix[:3, :3], np.eye(3), rtol=0, atol=1e-15)


_READERS = {"getPosition", "getRotation", "toNumPy", "asHomogeneousTransform", "inverse", "model"}


def test_no_idyntree_object_is_read_through_a_chained_temporary() -> None:
    # `kinDyn.getRelativeTransform(a, b).getPosition().toNumPy()` reads a freed Transform
    # (measured: x = 1e-313 where 0.07 was right), and `ModelLoader().model()` a freed
    # model (std::bad_alloc): every iDynTree result is kept in a variable before it is read.
    tree = ast.parse(inspect.getsource(idyntree_urdf))
    chained = [
        ast.unparse(node)
        for node in ast.walk(tree)
        if isinstance(node, ast.Attribute)
        and node.attr in _READERS
        and isinstance(node.value, ast.Call)
    ]
    assert chained == []
