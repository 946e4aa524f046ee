"""One small arm written twice, a URDF and its MJCF conversion (examples/conversion/), and faults.

Three revolute joints (one turning the other way), a quarter turn and a 0.5 rad
turn between links, and a tool frame (a URDF fixed joint, an MJCF site): what a
URDF → MJCF conversion must carry over. Each fault is a string replacement that
must change the MJCF (:func:`seeded`).
"""

from __future__ import annotations

from pathlib import Path

from tests.paths import REPO_ROOT

__all__ = ["FAULTS", "FOLDER", "MJCF", "URDF", "seeded", "write_pair"]

#: The two files, as a user would have them (docs/howto/check-a-conversion.md runs them).
FOLDER = REPO_ROOT / "examples" / "conversion"
URDF = (FOLDER / "arm.urdf").read_text(encoding="utf-8")
MJCF = (FOLDER / "arm.xml").read_text(encoding="utf-8")

#: Seeded conversion faults: name → (text in the right MJCF, its faulty replacement).
FAULTS = {
    # link3 1 mm further along link2's x: the table's a2.
    "body 1 mm off": ('<body name="link3" pos="0.3 0 0"', '<body name="link3" pos="0.301 0 0"'),
    "axis sign flipped": ('<joint name="j2" axis="0 0 1"', '<joint name="j2" axis="0 0 -1"'),
    # MuJoCo's default unit is the degree: the radians written are read as degrees.
    "radians read as degrees": ('  <compiler angle="radian"/>\n', ""),
}


def seeded(fault: str) -> str:
    """The MJCF with ``fault`` seeded (asserting the replacement changed it)."""
    old, new = FAULTS[fault]
    assert old in MJCF
    return MJCF.replace(old, new)


def write_pair(folder: Path, mjcf: str = MJCF) -> tuple[Path, Path]:
    """``(arm.urdf, arm.xml)`` written into ``folder``."""
    urdf, xml = folder / "arm.urdf", folder / "arm.xml"
    urdf.write_text(URDF, encoding="utf-8")
    xml.write_text(mjcf, encoding="utf-8")
    return urdf, xml
