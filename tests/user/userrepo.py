"""A throw-away user repository: the bundled UR5 as ``good.toml`` and one α of the wrong sign."""

from __future__ import annotations

from pathlib import Path

from fkcheck.model.read import bundled_model_paths

__all__ = ["WRONG_ALPHA", "bad_ur5_text", "good_ur5_text", "make_user_repo"]

#: What the bad model gets wrong, as the diagnosis names it.
WRONG_ALPHA = "α4 (wrist_1) has the wrong sign"


def good_ur5_text() -> str:
    """The bundled UR5 model file (its URDF is ``example-robot-data:…``, valid anywhere)."""
    return bundled_model_paths()["ur5"].read_text(encoding="utf-8")


def bad_ur5_text() -> str:
    """The UR5 with α4 (wrist_1) = -90° instead of 90°."""
    parts = good_ur5_text().split("[[joint]]")
    assert "alpha = 90\n" in parts[4]
    parts[4] = parts[4].replace("alpha = 90\n", "alpha = -90\n")
    return "[[joint]]".join(parts)


def make_user_repo(root: Path, tool_fkcheck: str) -> Path:
    """``pyproject.toml`` with ``tool_fkcheck`` as its ``[tool.fkcheck]``, robots/good and bad."""
    root.mkdir(parents=True, exist_ok=True)
    (root / "pyproject.toml").write_text(
        f'[project]\nname = "my-robots"\nversion = "0"\n\n[tool.fkcheck]\n{tool_fkcheck}',
        encoding="utf-8",
    )
    (root / "robots").mkdir(exist_ok=True)
    (root / "robots" / "good.toml").write_text(good_ur5_text(), encoding="utf-8")
    (root / "robots" / "bad.toml").write_text(bad_ur5_text(), encoding="utf-8")
    return root
