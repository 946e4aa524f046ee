"""Two readers of one description that disagree: the one that disagrees is a reader finding."""

from __future__ import annotations

import numpy as np

from fkcheck.engine.readers import apply_reader_findings
from fkcheck.engine.results import BackendResult
from fkcheck.engine.verdict import evidence_sentences, headline, summarize, verdict_of

N = 20
FORMATS = {"mujoco-mjcf": "mjcf", "pinocchio-mjcf": "mjcf", "pinocchio-urdf": "urdf"}
LIBRARIES = {
    "mujoco-mjcf": ("mujoco", "9.8.7"),
    "pinocchio-mjcf": ("pinocchio", "4.1.0"),
    "pinocchio-urdf": ("pinocchio", "4.1.0"),
}
FINDING = (
    "pinocchio-mjcf (pinocchio 4.1.0) disagrees with mujoco-mjcf (mujoco 9.8.7), which "
    "agrees with the table: a finding about the reader, not the table"
)


def row(name, status, *, error=0.0, evidence="table", subset=None, worst=0):
    err = np.full(N, error)
    return BackendResult(
        name, status, message="m", position_error_m=err, rotation_error_rad=err,
        evidence=evidence, subset=subset, worst_index=worst,
    )  # fmt: skip


def test_the_reader_that_disagrees_where_the_other_agrees_is_named_with_both_versions():
    results = [row("mujoco-mjcf", "pass"), row("pinocchio-mjcf", "fail", error=1.7)]
    out = apply_reader_findings(results, FORMATS, LIBRARIES)
    assert out[0].reader_finding == ""
    assert out[1].reader_finding == FINDING
    assert out[1].status == "fail"  # it still disagrees: never a silent pass
    assert out[1].message == f"{FINDING} — m"


def test_the_table_is_verified_by_the_agreeing_reader_and_the_check_still_fails():
    results = apply_reader_findings(
        [row("rtb-dh", "pass", evidence="implementation"), row("mujoco-mjcf", "pass"),
         row("pinocchio-mjcf", "fail", error=1.7)],
        FORMATS, LIBRARIES,
    )  # fmt: skip
    evidence = summarize(results)
    assert evidence.table.status == "verified"
    assert evidence.table.disagreed == ()
    assert evidence.table.readers == ("pinocchio-mjcf",)
    verdict = verdict_of(results, evidence)
    assert verdict == "fail"
    line = headline(verdict, evidence, 3)
    assert line.startswith("fail — a reader disagrees where another reader of the same")
    assert "table disagrees" not in line
    table_sentence = evidence_sentences(evidence)[1]
    assert table_sentence.startswith("table verified: mujoco-mjcf agrees")
    assert table_sentence.endswith(FINDING)


def test_both_readers_disagreeing_is_the_tables_failure_not_a_finding():
    results = [row("mujoco-mjcf", "fail", error=1e-3), row("pinocchio-mjcf", "fail", error=1.7)]
    out = apply_reader_findings(results, FORMATS, LIBRARIES)
    assert [r.reader_finding for r in out] == ["", ""]
    assert summarize(out).table.status == "failed"


def test_an_expected_failure_agrees_with_nothing():
    results = [row("mujoco-mjcf", "xfail", error=1e-3), row("pinocchio-mjcf", "fail", error=1.7)]
    assert [r.reader_finding for r in apply_reader_findings(results, FORMATS, LIBRARIES)] == [
        "",
        "",
    ]


def test_readers_of_another_format_are_not_compared():
    results = [row("pinocchio-urdf", "pass"), row("pinocchio-mjcf", "fail", error=1.7)]
    assert apply_reader_findings(results, FORMATS, LIBRARIES)[1].reader_finding == ""


def test_an_agreeing_reader_on_a_subset_must_have_seen_the_worst_configuration():
    unseen = [row("mujoco-mjcf", "pass", subset=(5, N)), row("pinocchio-mjcf", "fail", worst=7)]
    assert apply_reader_findings(unseen, FORMATS, LIBRARIES)[1].reader_finding == ""
    seen = [row("mujoco-mjcf", "pass", subset=(10, N)), row("pinocchio-mjcf", "fail", worst=7)]
    assert apply_reader_findings(seen, FORMATS, LIBRARIES)[1].reader_finding == FINDING


def test_a_reader_without_a_known_library_is_named_alone():
    results = [row("mujoco-mjcf", "pass"), row("pinocchio-mjcf", "fail", error=1.7)]
    out = apply_reader_findings(results, FORMATS, {})
    assert out[1].reader_finding.startswith("pinocchio-mjcf disagrees with mujoco-mjcf, which")


def test_a_backends_library_is_named_as_imported_with_its_installed_version():
    from importlib import metadata

    from fkcheck.backends.registry import make_backend
    from fkcheck.engine.expected import library_of

    assert library_of(make_backend("pinocchio-mjcf")) == ("pinocchio", metadata.version("pin"))
    assert library_of(make_backend("mujoco-mjcf")) == ("mujoco", metadata.version("mujoco-core"))
    assert library_of(make_backend("rtb-urdf")) == (
        "roboticstoolbox",
        metadata.version("roboticstoolbox-python"),
    )
    assert library_of(object()) is None  # names no distribution
