"""Reports: a finished check (and its diagnoses) formatted — never recomputed.

Data first, then templates. Nothing here runs a backend, the core, a parser or
the diagnosis: everything shown was gathered by the engine
(:class:`~fkcheck.engine.results.CheckResult`, each failing backend's
:class:`~fkcheck.engine.evidence.FailureDetail`) and by
:func:`fkcheck.diagnose.failures.diagnose_failures`.

* the record: :mod:`~fkcheck.report.record` — one per backend and one per
  check, built once; every format below (and the terminal, :mod:`fkcheck.testing`
  and the pytest plugin) reads its fields instead of deriving its own;
* :func:`~fkcheck.report.write.write_reports`: the one function that writes a
  check's files, for ``fkcheck check`` and :func:`fkcheck.write_report` alike;
* writers: :mod:`~fkcheck.report.json_report` (the JSON contract),
  :mod:`~fkcheck.report.junit`, :mod:`~fkcheck.report.markdown` (CI pages),
  :mod:`~fkcheck.report.html` (the self-contained page and the index);
* view models: :mod:`~fkcheck.report.views` (frozen dataclasses the Jinja2
  templates in ``templates/`` lay out), built by :mod:`~fkcheck.report.page`
  from :mod:`~fkcheck.report.backend_view`, :mod:`~fkcheck.report.partings`,
  :mod:`~fkcheck.report.model_view`, :mod:`~fkcheck.report.diagnosis` and
  :mod:`~fkcheck.report.index`; pictures by :mod:`~fkcheck.report.plots`;
* numbers: :mod:`~fkcheck.io.format` is the one formatter,
  :mod:`~fkcheck.report.measures` packs its strings into view values.

May import: every layer below (engine, diagnose and their types). Every writer
writes atomically (:func:`fkcheck.io.atomic.write_text_atomic`). Importing this
package imports no plotting or templating library.
"""

__all__: list[str] = []
