"""MJCF as the second description format: ``[mjcf]``, ``mjcf =`` frames, and its two readers."""

from __future__ import annotations

from dataclasses import replace

import pytest

from fkcheck.backends.base import contract_problems, reads_model_description
from fkcheck.backends.registry import make_backend, names
from fkcheck.description.registry import (
    format_named,
    load_description,
    model_formats,
    read_description_file,
)
from fkcheck.engine.runner import run_check
from fkcheck.errors import MjcfError
from fkcheck.model.read import bundled_models_dir, load_model

PANDA_MJCF = "fkcheck:mujoco_menagerie/franka_emika_panda/panda_nohand.xml"
JOINTS = [f"joint{i}" for i in range(1, 8)]
READERS = ("mujoco-mjcf", "pinocchio-mjcf")
#: Menagerie's flange site: the flange (the table's tcp) turned 135° about z.
SITE = """
[frames.attachment_site]
dh = "tcp"
rpy = [0.0, 0.0, 2.356194490192345]
mjcf = "attachment_site"
source = "Menagerie's panda_nohand.xml: attachment_site, quat (0.3826834, 0, 0, 0.9238795)"
"""


def panda(tmp_path, joints=JOINTS):
    """The bundled Panda table with Menagerie's MJCF as its second description."""
    text = (bundled_models_dir() / "panda.toml").read_text()
    for k in range(8):
        text = text.replace(
            f'urdf = "panda_link{k}"\n', f'urdf = "panda_link{k}"\nmjcf = "link{k}"\n'
        )
    listed = ", ".join(f'"{j}"' for j in joints)
    text += f'\n[mjcf]\npath = "{PANDA_MJCF}"\njoints = [{listed}]\n' + SITE
    path = tmp_path / "panda.toml"
    path.write_text(text)
    return load_model(path)


def test_a_model_with_mjcf_has_an_mjcf_description(tmp_path):
    model = panda(tmp_path)
    assert [f.name for f in model_formats(model)] == ["urdf", "mjcf"]
    described = load_description(model, language="mjcf")
    assert described.format == "mjcf"
    assert described.language == "mjcf"
    assert described.path.name == "panda_nohand.xml"
    assert {"world", "link0", "link7", "attachment_site"} <= set(described.frames)
    assert described.tree.kind == "MJCF" or described.tree.links[0] == "world"
    assert format_named("mjcf").mapped_joints(model) == tuple(JOINTS)
    assert model.frames["attachment_site"].mjcf == "attachment_site"


def test_its_two_readers_agree_with_the_table(tmp_path):
    model = panda(tmp_path)
    backends = [make_backend(n) for n in READERS]
    check = run_check(
        model, backends, samples=200, frame_from="panda_link0", frame_to="attachment_site"
    )
    rows = {r.name: r for r in check.backends}
    for name in READERS:
        assert rows[name].status == "pass", rows[name].message
        assert rows[name].evidence == "table"
    assert check.verdict == "pass"


def test_a_table_one_millimetre_off_fails_in_both_readers(tmp_path):
    model = panda(tmp_path)
    joints = list(model.joints)
    joints[2] = replace(joints[2], d=joints[2].d + 1e-3)
    wrong = replace(model, joints=tuple(joints))
    check = run_check(
        wrong, [make_backend(n) for n in READERS], samples=200,
        frame_from="panda_link0", frame_to="attachment_site",
    )  # fmt: skip
    rows = {r.name: r for r in check.backends}
    for name in READERS:
        assert rows[name].status == "fail", rows[name].message
        assert rows[name].max_position_error_m == pytest.approx(1e-3, rel=0.2)


def test_a_mapped_joint_the_mjcf_lacks_is_one_error_listing_its_joints(tmp_path):
    model = panda(tmp_path, joints=[*JOINTS[:6], "nope"])
    with pytest.raises(
        MjcfError,
        match=r"joint 'nope' \(for DH joint .*\) is not a hinge or slide joint of it; "
        r"its joints are: joint1, ",
    ):
        load_description(model, language="mjcf")


def test_the_readers_declare_mjcf_and_keep_the_contract(tmp_path):
    assert names(format="mjcf") == READERS
    assert names(reads="mjcf") == READERS
    model = panda(tmp_path)
    for name in READERS:
        backend = make_backend(name)
        assert contract_problems(backend) == []
        assert reads_model_description(backend, model)
        assert backend.unavailable_reason(load_model("ur5")) == "model has no [mjcf]"
    assert not reads_model_description(make_backend("mujoco-mjcf"), load_model("ur5"))


def test_a_file_named_on_the_command_line_is_read_as_mjcf_by_its_suffix():
    described = read_description_file(
        bundled_models_dir() / "mujoco_menagerie/franka_emika_panda/panda_nohand.xml"
    )
    assert described.format == "mjcf"
    assert "attachment_site" in described.frames


def test_its_readers_run_by_default_only_for_a_model_with_mjcf(tmp_path):
    from fkcheck.backends.registry import default_names

    plain = default_names()
    assert not set(READERS) & set(plain)
    assert default_names(load_model("ur5")) == plain  # no skipped rows for a model without [mjcf]
    assert default_names(panda(tmp_path)) == (*plain, *READERS)


def test_a_model_with_mjcf_only_leaves_out_the_urdf_readers():
    """Symmetric with a URDF-only model's MJCF readers: a reader of a file it lacks is no check."""
    from fkcheck.backends.registry import default_names

    plain = default_names()
    urdf_readers = [n for n in plain if n.endswith("-urdf")]
    assert len(urdf_readers) == 5
    assert default_names(load_model("ur5e_menagerie")) == (
        *(n for n in plain if n not in urdf_readers), *READERS,
    )  # fmt: skip
    assert default_names(load_model("planar2")) == plain  # no description: they say where to add
