"""The bundled MuJoCo Menagerie twins: read, their sources named, measured against the tables.

The DH side is fkcheck's in-house core (``Model.fk``, :mod:`fkcheck.core.dh`) on the
bundled tables; the MJCF side is MuJoCo's reader. Each number the two differ by is
named from the files themselves (``models/mujoco_menagerie/SOURCE.md`` says the same).
"""

from __future__ import annotations

import numpy as np
import pytest

from fkcheck.mjcf import compare_readers, mujoco_poses, pinocchio_poses, read_mjcf
from fkcheck.model.read import bundled_models_dir, load_model

MENAGERIE = bundled_models_dir() / "mujoco_menagerie"
TWINS = {
    "ur5e": ("universal_robots_ur5e/ur5e.xml", "LICENSE"),
    "ur10e": ("universal_robots_ur10e/ur10e.xml", "LICENSE.md"),
    "panda": ("franka_emika_panda/panda_nohand.xml", "LICENSE"),
    "xarm7": ("ufactory_xarm7/xarm7_nohand.xml", "LICENSE"),
}
#: Configurations drawn within each MJCF joint's range (seeded).
SAMPLES = 20_000
#: Two float64 chains of the same numbers agree to round-off.
EXACT = 1e-12


def twin(name: str):
    return read_mjcf(MENAGERIE / TWINS[name][0])


def within_limits(desc, n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    joints = [desc.kinematics.joints[j] for j in desc.joints]
    lo = np.array([j.limits[0] if j.limits else -np.pi for j in joints])
    hi = np.array([j.limits[1] if j.limits else np.pi for j in joints])
    return rng.uniform(lo, hi, (n, len(joints)))


@pytest.mark.parametrize("name", sorted(TWINS))
def test_twin_is_bundled_with_licence_and_source(name: str) -> None:
    xml, licence = TWINS[name]
    folder = (MENAGERIE / xml).parent
    assert (folder / licence).read_text().strip()
    source = (MENAGERIE / "SOURCE.md").read_text()
    assert f"`{xml}`" in source
    text = (MENAGERIE / xml).read_text()
    assert "mujoco_menagerie" in source
    assert "commit" in text
    for absent in ("<geom", "<mesh", "<asset", "meshdir", "<inertial"):
        assert absent not in text


@pytest.mark.parametrize("name", sorted(TWINS))
def test_twin_joints_are_the_tables(name: str) -> None:
    desc = twin(name)
    model = load_model(name)
    assert len(desc.joints) == len(model.joints)
    assert "attachment_site" in desc.sites
    q = within_limits(desc, 200)
    tree = desc.kinematics.chain_poses(desc.kinematics.chain("world", "attachment_site"), q)
    np.testing.assert_allclose(
        tree[:, -1], mujoco_poses(desc, ["attachment_site"], q)[0], atol=EXACT
    )


def test_ur5e_world_is_the_dh_base_and_the_site_the_flange_within_1_49_mm() -> None:
    desc = twin("ur5e")
    model = load_model("ur5e")
    q = within_limits(desc, SAMPLES)
    mj = mujoco_poses(desc, ["attachment_site"], q)[0]
    dh = model.fk(q)  # DH frame 6 (tool0) in DH frame 0 (base)
    position = np.linalg.norm(mj[:, :3, 3] - dh[:, :3, 3], axis=1)
    # Orientation: the site is the flange exactly (quat "1 0 1 0" and "-1 1 0 0" are exact).
    relative = np.swapaxes(dh[:, :3, :3], 1, 2) @ mj[:, :3, :3]
    np.testing.assert_allclose(relative, np.broadcast_to(np.eye(3), relative.shape), atol=1e-12)
    # The measurement: up to 1.49 mm at the flange.
    assert position.max() == pytest.approx(1.49e-3, abs=0.005e-3)
    assert position.min() > 0.3e-3  # never zero: the numbers differ, not one configuration


def test_ur5e_numbers_name_the_difference() -> None:
    """Menagerie's numbers are UR's rounded to the millimetre: each one named, from the files."""
    kin = twin("ur5e").kinematics
    table = {j.name: j for j in load_model("ur5e").joints}
    at = {name: kin.joints[name].origin[:3, 3] for name in kin.joints}
    site = kin.joints["site:attachment_site"].origin[:3, 3]
    menagerie = {
        "d1": at["shoulder_pan_joint"][2],
        "a2": at["elbow_joint"][2],
        "a3": at["wrist_1_joint"][2],
        # the y offsets of upper_arm_link, forearm_link and wrist_2_link: 0.138 − 0.131 + 0.127
        "d4": at["shoulder_lift_joint"][1] + at["elbow_joint"][1] + at["wrist_2_joint"][1],
        "d5": at["wrist_3_joint"][2],
        "d6": site[1],
    }
    ur = {
        "d1": table["shoulder_pan"].d,
        "a2": -table["shoulder_lift"].a,
        "a3": -table["elbow"].a,
        "d4": table["wrist_1"].d,
        "d5": table["wrist_2"].d,
        "d6": table["wrist_3"].d,
    }
    differences = {k: round(float(menagerie[k] - ur[k]) * 1e3, 4) for k in ur}
    assert differences == {"d1": 0.5, "a2": 0.0, "a3": -0.2, "d4": 0.7, "d5": 0.3, "d6": 0.4}


def test_ur5e_a_table_with_menageries_numbers_agrees_exactly() -> None:
    """The 1.49 mm is those five numbers and nothing else: change them and it is round-off."""
    from dataclasses import replace

    model = load_model("ur5e")
    rounded = {
        "shoulder_pan": {"d": 0.163},
        "elbow": {"a": -0.392},
        "wrist_1": {"d": 0.134},
        "wrist_2": {"d": 0.100},
        "wrist_3": {"d": 0.100},
    }
    joints = [replace(j, **rounded.get(j.name, {})) for j in model.joints]
    menagerie_table = replace(model, joints=tuple(joints))
    desc = twin("ur5e")
    q = within_limits(desc, 2000, seed=1)
    mj = mujoco_poses(desc, ["attachment_site"], q)[0]
    np.testing.assert_allclose(mj, menagerie_table.fk(q), atol=1e-12)


def test_ur5e_pinocchio_drops_the_base_bodys_turn_and_is_named() -> None:
    """pinocchio#2782 on Menagerie's own UR5e: the jointless `base` body's quat is dropped."""
    desc = twin("ur5e")
    model = load_model("ur5e")
    q = within_limits(desc, 2000, seed=2)
    held = compare_readers(
        desc, ["attachment_site"], q, reference=("the DH table", model.fk(q)[None]), tol_pos_m=2e-3
    )
    results = {r.reader: r for r in held.results}
    assert results["mujoco-mjcf"].position_m < 1.5e-3  # the rounding above, within 2 mm
    import pinocchio

    if pinocchio.__version__ == "4.1.0":
        assert held.disagreeing == ("pinocchio-mjcf",)
        assert results["pinocchio-mjcf"].rotation_rad == pytest.approx(np.pi, abs=1e-9)
        assert results["pinocchio-mjcf"].position_m > 1.8  # up to 1.9 m: the arm turned π


def test_ur10e_flange_is_16_55_mm_short_of_urs_d6() -> None:
    kin = twin("ur10e").kinematics
    site_y = kin.joints["site:attachment_site"].origin[1, 3]
    d6 = load_model("ur10e").joints[5].d
    assert round((site_y - d6) * 1e3, 3) == -16.55
    desc = twin("ur10e")
    q = within_limits(desc, SAMPLES)
    mj = mujoco_poses(desc, ["attachment_site"], q)[0]
    position = np.linalg.norm(mj[:, :3, 3] - load_model("ur10e").fk(q)[:, :3, 3], axis=1)
    assert position.max() == pytest.approx(17.7e-3, abs=0.05e-3)


def test_panda_link0_is_the_dh_base_and_positions_agree() -> None:
    desc = twin("panda")
    model = load_model("panda")
    q = within_limits(desc, 2000)
    frames = ["link0", *(f"link{i}" for i in range(1, 8)), "attachment_site"]
    mj = mujoco_poses(desc, frames, q)
    dh = model.fk(q, all_frames=True)  # DH frames 0..7
    np.testing.assert_allclose(mj[:8], np.moveaxis(dh, 1, 0), atol=EXACT)
    tcp = model.fk(q)
    np.testing.assert_allclose(mj[8][:, :3, 3], tcp[:, :3, 3], atol=EXACT)
    turn = np.swapaxes(tcp[:, :3, :3], 1, 2) @ mj[8][:, :3, :3]  # the site's own 135° about z
    c, s = np.cos(np.radians(135)), np.sin(np.radians(135))
    np.testing.assert_allclose(
        turn, np.broadcast_to([[c, -s, 0], [s, c, 0], [0, 0, 1]], turn.shape), atol=1e-7
    )


def test_xarm7_link_base_is_the_dh_base_120_mm_above_world() -> None:
    desc = twin("xarm7")
    model = load_model("xarm7")
    q = within_limits(desc, 2000)
    for reader in (mujoco_poses,):
        base, site = reader(desc, ["link_base", "attachment_site"], q)
        np.testing.assert_allclose(base[0, :3, 3], [0, 0, 0.12], atol=EXACT)
        np.testing.assert_allclose(np.linalg.inv(base) @ site, model.fk(q), atol=EXACT)


def test_xarm7_pinocchio_agrees_with_the_table_for_the_wrong_reason() -> None:
    """Pinocchio 4.1.0 drops `link_base`'s 0.12 m (pinocchio#2782), so in `world` it
    lands on the DH table, and MuJoCo does not: only the base's own pose tells them apart."""
    import pinocchio

    desc = twin("xarm7")
    q = within_limits(desc, 50)
    base = pinocchio_poses(desc, ["link_base"], q)[0]
    if pinocchio.__version__ == "4.1.0":
        np.testing.assert_allclose(base[:, :3, 3], 0.0, atol=EXACT)
    held = compare_readers(desc, ["link_base"], q)  # no table: the two readers differ
    assert held.disagreeing == (
        () if pinocchio.__version__ != "4.1.0" else ("mujoco-mjcf", "pinocchio-mjcf")
    )
