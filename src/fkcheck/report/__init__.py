"""Writers of check results: JSON (the contract), JUnit XML, HTML pages and a Markdown summary.

* :mod:`~fkcheck.report.json_report` — the JSON result other tools read;
* :mod:`~fkcheck.report.junit` — JUnit XML, one test case per backend;
* :mod:`~fkcheck.report.html` — the self-contained HTML report and index page:
  :mod:`~fkcheck.report.build` turns results into the view models of
  :mod:`~fkcheck.report.views`, which the Jinja2 templates in ``templates/``
  lay out; :mod:`~fkcheck.report.plots` draws the pictures,
  :mod:`~fkcheck.engine.evidence` gathers what the page shows beyond the
  check's numbers (both matrices at the worst configurations, where the chains
  part; the joint axes against the URDF come from :mod:`fkcheck.diagnose.axes`);
  :mod:`~fkcheck.report.diagnosis` lays out the diagnoses
  against a failed check's disagreeing backends for the page's Diagnosis section;
* :mod:`~fkcheck.report.markdown` — the short summary for CI pages.

Every writer writes atomically (:func:`fkcheck.io.atomic.write_text_atomic`):
an interrupted run never leaves a truncated file behind. Importing this package
imports no plotting or templating library; each module imports those inside the
functions that need them.
"""

__all__: list[str] = []
