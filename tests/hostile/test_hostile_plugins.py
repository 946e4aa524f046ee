"""A model file can name no code to run: no plugin it names is ever imported.

Plugins (``--against module:function``) are imported from the working directory
(:func:`fkcheck.backends.plugin.search_path`); a model is input, so the names it
holds (``[[known_difference]] backends``) are compared as text and never built.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

from tests.paths import REPO_ROOT


def test_a_plugin_a_model_names_is_never_imported(tmp_path):
    marker = tmp_path / "ran"
    (tmp_path / "evil.py").write_text(
        f"open({str(marker)!r}, 'w').write('imported')\ndef run(q):\n    return q\n"
    )
    model = tmp_path / "ur5_evil.toml"
    model.write_text(
        (REPO_ROOT / "models" / "ur5.toml").read_text()
        + textwrap.dedent("""
            [[known_difference]]
            backends = ["evil:run"]
            finding = "names a plugin"
            max_position_m = 0.001
            max_angle_rad = 0.001
        """)
    )
    paths = [str(REPO_ROOT), os.environ.get("PYTHONPATH", "")]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in paths if p)}
    for command in ("check", "lint", "diagnose"):
        done = subprocess.run(
            [sys.executable, "-P", "-m", "fkcheck", command, str(model)],
            cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600, check=False,
        )  # fmt: skip
        assert done.returncode == 2, (command, done.stdout + done.stderr)
        assert "known_difference[0].backends[0]: 'evil:run' is not a backend" in done.stderr
        assert not marker.exists(), command
