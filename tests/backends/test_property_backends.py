"""Property-based: random DH tables agree across the in-house core and the reference backends.

Two families, the same random tables (:mod:`strategies`):

* the DH backends (``rtb-dh``, ``pinocchio-dh``) rebuild the table in their library;
  every DH frame and the TCP must match the core to :data:`SAME_CHAIN`;
* the table exported as a URDF (:func:`fkcheck.urdf.export.urdf_from_model`, numbers
  written to round-trip) must match the core in all three URDF backends, every DH
  frame included. Each example writes a file and loads three parsers, so this one
  runs a fifth of the profile's examples.

Every output must also be a valid SE(3). ``nox -s fuzz`` runs 10x the examples.

One library limit is screened out: trimesh's ``SceneGraph.get`` (under yourdfpy)
drops every edge within 1e-8 of the identity on a path of two or more edges, so
a table with a tiny non-zero angle or length (1e-9) reads as if it were zero in
yourdfpy-urdf only. Those configurations are left out of yourdfpy's comparison
(:func:`trimesh_drops_an_edge`); the shrunk examples hypothesis found are pinned
below as regression tests.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import fkcheck.backends.registry as registry
from fkcheck.core.geometry import invert, matrix_from_xyz_rpy, rot_z, translation
from fkcheck.core.tolerances import SAME_CHAIN
from fkcheck.model.read import model_from_dict
from fkcheck.urdf.export import model_for_urdf, urdf_from_model
from tests.backend_cases import URDF_BACKENDS
from tests.helpers import assert_pose_close, assert_se3, random_q
from tests.strategies import dh_models

DH_BACKENDS = ("rtb-dh", "pinocchio-dh")
#: trimesh.scene.transforms.SceneGraph.get: ``np.abs(m - _identity).max() > 1e-8`` keeps an edge.
TRIMESH_IDENTITY_CUTOFF = 1e-8


@pytest.fixture(scope="module")
def dh_backends():
    return {name: registry.make_backend(name) for name in DH_BACKENDS}


@pytest.fixture(scope="module")
def urdf_backends():
    return {name: registry.make_backend(name) for name in URDF_BACKENDS}


def _assert_matches_core(name, model, q, world_T_frames, tcp):
    """``world_T_frames`` (N, n+1, 4, 4) and ``tcp`` (N, 4, 4) against the core."""
    assert_se3(world_T_frames, SAME_CHAIN)
    assert_se3(tcp, SAME_CHAIN)
    assert_pose_close(world_T_frames, model.fk(q, all_frames=True), SAME_CHAIN, f"{name} frames")
    assert_pose_close(tcp, model.fk(q), SAME_CHAIN, f"{name} tcp")


def check_dh_backends(backends, model, seed):
    q = random_q(model, np.random.default_rng(seed), 8)
    for name, backend in backends.items():
        assert backend.unavailable_reason(model) is None, name
        (world, tcp) = backend.frame_poses(model, q, ["world", "tcp"])
        tcp = invert(world) @ tcp
        _assert_matches_core(name, model, q, backend.dh_frames(model, q), tcp)


def trimesh_drops_an_edge(urdf_text, model, q_row):
    """Whether an edge of the URDF's tree at ``q_row`` is near, but not at, the identity.

    Recomputed from the URDF text (origin times the joint's motion about its z axis),
    independently of yourdfpy.
    """
    values = dict(zip(model.joint_names, q_row, strict=True))
    for joint in ET.fromstring(urdf_text).iter("joint"):
        origin = joint.find("origin")
        edge = matrix_from_xyz_rpy(
            [float(v) for v in origin.get("xyz").split()],
            [float(v) for v in origin.get("rpy").split()],
        )
        if joint.get("name") in values:
            v = values[joint.get("name")] * float(joint.find("axis").get("xyz").split()[2])
            edge = edge @ (
                translation(0.0, 0.0, v) if joint.get("type") == "prismatic" else rot_z(v)
            )
        if 0.0 < np.abs(edge - np.eye(4)).max() <= TRIMESH_IDENTITY_CUTOFF:
            return True
    return False


def urdf_backend_poses(backend, model, q, directory):
    """``world_T_i`` (N, n+1, 4, 4) and ``world_T_tcp`` (N, 4, 4) from the exported URDF."""
    export = urdf_from_model(model)
    path = directory / "robot.urdf"
    path.write_text(export.text, encoding="utf-8")
    mapped = model_for_urdf(model, export, str(path))
    assert backend.unavailable_reason(mapped) is None, backend.name
    dh_names = [f"dh_frame_{i}" for i in range(model.dof + 1)]
    world, tcp, *frames = backend.frame_poses(mapped, q, ["world", "tcp", *dh_names])
    world_T_root = invert(world)
    return np.stack([world_T_root @ T for T in frames], axis=1), world_T_root @ tcp


def check_urdf_backends(backends, model, seed, directory):
    q = random_q(model, np.random.default_rng(seed), 4)
    text = urdf_from_model(model).text
    for name, backend in backends.items():
        keep = np.ones(len(q), dtype=bool)
        if name == "yourdfpy-urdf":
            keep = np.array([not trimesh_drops_an_edge(text, model, row) for row in q])
        world_T_frames, tcp = urdf_backend_poses(backend, model, q, directory)
        assert_se3(world_T_frames, SAME_CHAIN)
        assert_se3(tcp, SAME_CHAIN)
        _assert_matches_core(name, model, q[keep], world_T_frames[keep], tcp[keep])


@given(model=dh_models(), seed=st.integers(0, 2**32 - 1))
def test_dh_backends_match_core_on_random_tables(dh_backends, model, seed):
    check_dh_backends(dh_backends, model, seed)


@settings(max_examples=max(1, settings().max_examples // 5))
@given(model=dh_models(), seed=st.integers(0, 2**32 - 1))
def test_urdf_export_matches_core_in_urdf_backends_on_random_tables(
    urdf_backends, tmp_path_factory, model, seed
):
    directory = tmp_path_factory.mktemp("random_urdf")
    check_urdf_backends(urdf_backends, model, seed, directory)


# Shrunk examples hypothesis found (trimesh's identity cut-off, a library limit):
# yourdfpy-urdf reads a 1e-9 rad joint offset at q = 0 as no rotation at all, while
# pinocchio-urdf and rtb-urdf keep it to SAME_CHAIN.
TINY_THETA = {
    "name": "random",
    "convention": "standard",
    "joint": [
        {
            "name": "j0",
            "type": "revolute",
            "a": 0.0,
            "alpha": 0.0,
            "d": 0.0,
            "theta": 1e-9,
            "limits": [0.0, 0.0],
        }
    ],
}


def test_tiny_joint_offset_is_kept_by_pinocchio_and_rtb_urdf(urdf_backends, tmp_path):
    model = model_from_dict(TINY_THETA)
    q = np.zeros((1, 1))
    expected = rot_z(1e-9)  # independent of the core: the table is one Rz(θ)
    assert_pose_close(model.fk(q), expected[None], SAME_CHAIN)
    for name in ("pinocchio-urdf", "rtb-urdf"):
        frames, tcp = urdf_backend_poses(urdf_backends[name], model, q, tmp_path)
        assert_pose_close(tcp, expected[None], SAME_CHAIN, name)
        assert_pose_close(frames[:, 1], expected[None], SAME_CHAIN, name)


def test_tiny_joint_offset_is_dropped_by_yourdfpy_urdf(urdf_backends, tmp_path):
    model = model_from_dict(TINY_THETA)
    q = np.zeros((1, 1))
    assert trimesh_drops_an_edge(urdf_from_model(model).text, model, q[0])
    _, tcp = urdf_backend_poses(urdf_backends["yourdfpy-urdf"], model, q, tmp_path)
    np.testing.assert_array_equal(tcp[0], np.eye(4))  # the 1e-9 rad turn is lost
