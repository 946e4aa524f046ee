"""View models of the HTML pages: everything the templates show, already formatted.

Built by :mod:`fkcheck.report.page` and :mod:`fkcheck.report.index` from a check
result; rendered by the Jinja2 templates in ``fkcheck/report/templates``
(autoescaped), which only lay them out. Every field is plain text, numbers or
nested view models: no NumPy arrays and no markup reach a template, so all text
from a model file or URDF is escaped on output. One concept (the pages' data,
no logic), one module per part of the pages: :mod:`.cells` (the pieces every
part shows), :mod:`.backend`, :mod:`.jacobian`, :mod:`.diagnosis`, :mod:`.model`,
:mod:`.page` (a check's page) and :mod:`.index` (the index page); every view is
importable from here.
"""

from __future__ import annotations

from fkcheck.report.views.backend import (
    ArmDrawing,
    BackendDetail,
    BackendRow,
    FrameSide,
    PartingRow,
    PartingView,
    WorstCase,
)
from fkcheck.report.views.cells import (
    Fact,
    Image,
    JointValue,
    MatrixCell,
    MatrixView,
    Measure,
    PoseForms,
)
from fkcheck.report.views.diagnosis import AxisView, DiagnosisView, ExplanationView
from fkcheck.report.views.index import IndexModel, IndexPage, IndexRow
from fkcheck.report.views.jacobian import JacobianCell, JacobianRow, JacobianSection
from fkcheck.report.views.model import DhRow, FrameRow, ModelView, TransformView
from fkcheck.report.views.page import EvidenceLine, NumberRow, NumbersView, ReportPage

__all__ = [
    "ArmDrawing",
    "AxisView",
    "BackendDetail",
    "BackendRow",
    "DhRow",
    "DiagnosisView",
    "EvidenceLine",
    "ExplanationView",
    "Fact",
    "FrameRow",
    "FrameSide",
    "Image",
    "IndexModel",
    "IndexPage",
    "IndexRow",
    "JacobianCell",
    "JacobianRow",
    "JacobianSection",
    "JointValue",
    "MatrixCell",
    "MatrixView",
    "Measure",
    "ModelView",
    "NumberRow",
    "NumbersView",
    "PartingRow",
    "PartingView",
    "PoseForms",
    "ReportPage",
    "TransformView",
    "WorstCase",
]
