"""An outcome in a notebook: ``_repr_html_`` and ``repr``, laid out from the check's record."""

from __future__ import annotations

import re

import pytest
from markupsafe import escape

import fkcheck
from fkcheck.report.record import check_record

ROWS = [(0.3, 0.0, 0.0, 0.0), (0.2, 0.0, 0.0, 0.0)]


@pytest.fixture(scope="module")
def outcome() -> fkcheck.Outcome:
    model = fkcheck.model_from_table("<script>alert('x')</script> & co", ROWS)
    return fkcheck.check(model, against=["rtb-dh", "pinocchio-urdf"], samples=20, diagnose=False)


def test_the_model_name_is_escaped(outcome):
    page = outcome._repr_html_()
    assert "<script" not in page
    assert "<code>&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt; &amp; co</code>" in page


def test_it_shows_the_records_verdict_headline_and_backends(outcome):
    record = check_record(outcome.check, outcome.diagnoses)
    page = outcome._repr_html_()
    assert f'data-verdict="{record.verdict}"' in page
    assert escape(record.headline) in page
    rows = re.findall(r'<tr data-backend="([^"]+)">(.*?)</tr>', page, re.DOTALL)
    assert [name for name, _ in rows] == ["rtb-dh", "pinocchio-urdf"]
    for (_, row), b in zip(rows, record.backends, strict=True):
        assert f">{b.status}<" in row
        shown = b.numbers if b.ran else b.message
        assert escape(shown) in row
    assert record.backends[1].status == "skipped"  # a table has no URDF: its reason is shown


def test_repr_is_one_short_line(outcome):
    text = repr(outcome)
    assert "\n" not in text
    assert text.startswith("<fkcheck.Outcome ")
    assert outcome.headline in text
    assert "(1 of 2 backends ran)>" in text
