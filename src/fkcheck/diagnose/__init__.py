"""Diagnose a disagreement: which frame, which parameter, which typical mistake.

``fkcheck check`` says *that* a table and a reference disagree; this package
says *why*, most likely explanation first, each with its evidence: constant
frame offsets (``base_link`` vs ``base``), joint axes compared as lines, typical
mistakes tested as hypotheses, single parameters and finally every parameter
fitted to the reference. :func:`diagnose_jacobian` does the same for two
Jacobians whose poses agree: which convention (reference frame, row order,
column signs, a point offset) would make them agree.
"""

from fkcheck.diagnose.findings import Diagnosis, Explanation, format_text, to_dict
from fkcheck.diagnose.jacobian import JacobianDiagnosis, column_errors, diagnose_jacobian
from fkcheck.diagnose.run import diagnose

__all__ = [
    "Diagnosis",
    "Explanation",
    "JacobianDiagnosis",
    "column_errors",
    "diagnose",
    "diagnose_jacobian",
    "format_text",
    "to_dict",
]
