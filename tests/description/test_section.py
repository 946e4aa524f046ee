"""SectionFormat: what a format reads by the names of its section and frame key alone."""

from __future__ import annotations

from dataclasses import dataclass, replace

import pytest

from fkcheck.description.registry import FORMATS
from fkcheck.description.section import SectionFormat
from fkcheck.model.read import load_model
from fkcheck.model.types import FrameSpec, MjcfSpec

SIX = ("a", "b", "c", "d", "e", "f")


@dataclass(frozen=True)
class Named(SectionFormat):
    """A format that gives its two names and nothing else, as a third one would."""

    section: str
    frame_key: str


@pytest.mark.parametrize(("key", "other"), [("urdf", "mjcf"), ("mjcf", "urdf")])
def test_a_format_that_gives_only_its_names_reads_its_section(key, other):
    ur5 = load_model("ur5")
    assert ur5.urdf is not None
    spec = {"urdf": ur5.urdf, "mjcf": MjcfSpec("ur5.xml", ur5.urdf.joints)}[key]
    model = replace(ur5, **{key: spec, other: None})
    fmt, absent = Named(key, key), Named(other, other)
    assert fmt.declared_by(model)
    assert not absent.declared_by(model)
    assert fmt.mapped_joints(model) == ur5.urdf.joints
    assert absent.mapped_joints(model) == ()
    assert fmt.written(model) == spec.path
    renamed = fmt.remapped(model, SIX)
    assert fmt.mapped_joints(renamed) == SIX
    assert fmt.written(renamed) == spec.path  # only the joints changed
    frame = fmt.with_frame(FrameSpec("tool0", 6), "flange")
    assert fmt.frame(frame) == "flange"
    assert absent.frame(frame) is None


@pytest.mark.parametrize("fmt", FORMATS, ids=lambda f: f.name)
def test_every_shipped_format_is_a_section_format_over_its_own_names(fmt):
    assert isinstance(fmt, SectionFormat)
    assert fmt.section == fmt.frame_key == fmt.language  # [urdf]/urdf =, [mjcf]/mjcf =
