"""View models of the HTML pages: everything the templates show, already formatted.

Built by :mod:`fkcheck.report.page` and :mod:`fkcheck.report.index` from a check
result; rendered by the Jinja2 templates in ``fkcheck/report/templates``
(autoescaped), which only lay them out. Every field is plain text, numbers or
nested view models: no NumPy arrays and no markup reach a template, so all text
from a model file or URDF is escaped on output. One concept (the pages' data,
no logic), hence one module despite its length.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "ArmDrawing",
    "AxisView",
    "BackendDetail",
    "BackendRow",
    "DhRow",
    "DiagnosisView",
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


@dataclass(frozen=True)
class JacobianCell:
    """One joint column of one backend: its largest differences.

    Attributes:
        linear: Largest linear difference of the column (m/rad), formatted.
        angular: Largest angular difference (rad/rad), formatted.
        bad: Beyond the tolerance.
        first: The first joint whose column disagrees, for this backend.
    """

    linear: str
    angular: str
    bad: bool
    first: bool


@dataclass(frozen=True)
class JacobianRow:
    """One backend's Jacobian comparison.

    Attributes:
        name: Backend name.
        status: ``pass``, ``fail``, ``error`` or ``skipped``.
        linear: Largest linear difference, formatted (``–`` if not compared).
        angular: Largest angular difference, formatted.
        method: Its library's Jacobian, or the finite differences of its poses.
        tolerance: The tolerance applied to it, formatted.
        message: Why it failed, errored or was skipped.
        first_column: The first joint whose column disagrees (``""`` when none).
        diagnosis: Which convention would make it agree (``""`` when not diagnosed).
        diagnosis_details: The diagnosis's further lines.
        cells: One per joint column (empty if not compared).
    """

    name: str
    status: str
    linear: str
    angular: str
    method: str
    tolerance: str
    message: str
    first_column: str
    diagnosis: str
    diagnosis_details: tuple[str, ...]
    cells: tuple[JacobianCell, ...]


@dataclass(frozen=True)
class JacobianSection:
    """The Jacobian section of a report.

    Attributes:
        reference: ``world-aligned``, ``local`` or ``world``.
        target: The frame whose Jacobian is compared (the check's ``to``).
        meaning: What that reference frame is, for this check's frames.
        tolerance: The asked tolerance, formatted.
        joints: Column headers, one per joint.
        rows: One per backend that was asked.
    """

    reference: str
    target: str
    meaning: str
    tolerance: str
    joints: tuple[str, ...]
    rows: tuple[JacobianRow, ...]


@dataclass(frozen=True)
class Measure:
    """A number shown two ways, with its exact value kept for machines.

    Attributes:
        value: The exact value in SI units (m or rad), or ``None`` when absent.
        primary: The human reading, e.g. ``"0.300 mm"`` or ``"6.88e-15°"``.
        secondary: The SI value, e.g. ``"3.00e-04 m"`` or ``"1.20e-16 rad"``.
    """

    value: float | None
    primary: str
    secondary: str


@dataclass(frozen=True)
class Fact:
    """One line of a key/value list.

    Attributes:
        label: What it is.
        value: The value as text.
        volatile: Non-empty when the value changes from run to run or machine to
            machine (``"date"``, ``"version"``, ``"path"``, ``"duration"``); the
            template marks it ``data-volatile`` so gold tests can scrub it.
        code: Show the value as code.
    """

    label: str
    value: str
    volatile: str = ""
    code: bool = False


@dataclass(frozen=True)
class FrameSide:
    """One side of the compared frame pair and what it means.

    Attributes:
        role: ``"from"`` or ``"to"``.
        name: The named frame.
        placement: Where it sits on the DH chain, e.g. ``"DH frame 0"``.
        offset: Its fixed offset from there, or ``"none"``.
        urdf: Its URDF twin, e.g. ``"link base"``, or a note that it has none.
    """

    role: str
    name: str
    placement: str
    offset: str
    urdf: str


@dataclass(frozen=True)
class BackendRow:
    """One backend's line in the summary table.

    Attributes:
        name: Backend name.
        anchor: HTML id of its detail section (empty when it has none).
        status: ``pass``, ``fail``, ``error``, ``skipped``, ``xfail``, ``xpass``.
        method: The library call it used.
        duration: Wall time, formatted.
        message: Why it was skipped or errored, or the failure summary, in full.
        pos_max: Largest position error.
        pos_p99: 99th percentile of the position error.
        pos_median: Median position error.
        rot_max: Largest rotation error.
        rot_p99: 99th percentile of the rotation error.
        rot_median: Median rotation error.
        worst_q: The worst configuration, formatted (empty when it did not run).
        worst_origin: Where the worst configuration came from (``random``, ``pose:home`` …).
    """

    name: str
    anchor: str
    status: str
    method: str
    duration: str
    message: str
    pos_max: Measure
    pos_p99: Measure
    pos_median: Measure
    rot_max: Measure
    rot_p99: Measure
    rot_median: Measure
    worst_q: str
    worst_origin: str


@dataclass(frozen=True)
class Image:
    """A picture embedded in the page.

    Attributes:
        src: A ``data:`` URI (PNG, base64): no file or network access is needed.
        alt: Text alternative.
        caption: What is drawn and how to read it.
    """

    src: str
    alt: str
    caption: str


@dataclass(frozen=True)
class MatrixCell:
    """One entry of a 4×4 matrix.

    Attributes:
        text: The value as shown.
        marked: The two matrices differ here by more than the tolerance.
    """

    text: str
    marked: bool = False


@dataclass(frozen=True)
class MatrixView:
    """A 4×4 matrix: four rows of four cells."""

    rows: tuple[tuple[MatrixCell, ...], ...]


@dataclass(frozen=True)
class PoseForms:
    """A pose as a matrix and in compact forms.

    Attributes:
        matrix: The 4×4 homogeneous transform.
        xyz: Translation, metres.
        quaternion: Unit quaternion ``(x, y, z, w)`` (scalar last, w ≥ 0).
        rpy: Fixed-axis roll, pitch, yaw (URDF convention), degrees.
    """

    matrix: MatrixView
    xyz: str
    quaternion: str
    rpy: str


@dataclass(frozen=True)
class JointValue:
    """One joint value of a configuration.

    Attributes:
        joint: Joint name.
        rad: The value in radians (or metres for a prismatic joint).
        deg: The value in degrees (empty for a prismatic joint).
    """

    joint: str
    rad: str
    deg: str


@dataclass(frozen=True)
class WorstCase:
    """One of a backend's worst configurations, both poses side by side.

    Attributes:
        rank: 1 for the worst.
        index: Index of the configuration in the check.
        origin: Where it came from (``random``, ``corner``, ``pose:home`` …).
        q: The joint values.
        position_error: Position error at this configuration.
        rotation_error: Rotation error at this configuration.
        ours: The in-house ``from_T_to``.
        theirs: The backend's ``from_T_to`` as the check compared it.
        difference: ``theirs − ours``.
    """

    rank: int
    index: int
    origin: str
    q: tuple[JointValue, ...]
    position_error: Measure
    rotation_error: Measure
    ours: PoseForms
    theirs: PoseForms
    difference: MatrixView


@dataclass(frozen=True)
class PartingRow:
    """One DH frame compared between two chains at one configuration.

    Attributes:
        frame: Label, e.g. ``"DH frame 2 (after joint shoulder_lift)"``.
        position_error: Distance between the two frames' origins.
        rotation_error: Angle between the two frames' orientations.
        differs: Beyond tolerance.
        first: This is the first frame that differs.
    """

    frame: str
    position_error: Measure
    rotation_error: Measure
    differs: bool
    first: bool


@dataclass(frozen=True)
class PartingView:
    """Where two chains part: every DH frame (or joint axis) compared at one configuration.

    Attributes:
        title: What is compared, e.g. ``"rtb-dh: DH frames T_0_i"``.
        verdict: One sentence naming the first frame that differs (or saying none does).
        parted: Some frame differs.
        short: Where they part, in a few words, for the page's first screen
            (empty when they do not).
        what: How the comparison is made.
        rows: One row per frame.
    """

    title: str
    verdict: str
    parted: bool
    short: str
    what: str
    rows: tuple[PartingRow, ...]


@dataclass(frozen=True)
class ArmDrawing:
    """The 3D stick drawing of the arm at a backend's worst configuration."""

    image: Image


@dataclass(frozen=True)
class BackendDetail:
    """Everything about one disagreeing backend.

    Attributes:
        name: Backend name.
        anchor: HTML id.
        summary: One line: how many configurations differ and by how much.
        worst_q: The worst configuration, formatted.
        arm: The stick drawing at the worst configuration.
        worst_cases: The worst few configurations with both poses.
    """

    name: str
    anchor: str
    summary: str
    worst_q: str
    arm: ArmDrawing | None
    worst_cases: tuple[WorstCase, ...]


@dataclass(frozen=True)
class ExplanationView:
    """One explanation of a disagreement, with its evidence.

    Attributes:
        rank: 1 for the most likely.
        kind: What kind of mistake: ``frames``, ``mapping``, ``degrees``,
            ``convention``, ``conventions``, ``sign``, ``flip``, ``theta-offset``,
            ``parameter``, ``offset`` or ``fit``.
        title: One line that says it.
        explains: The change makes the disagreement vanish (within tolerance).
        verdict: ``"explains it"`` or ``"explains part of it"``.
        position_after: Position disagreement left once the table is changed this way.
        rotation_after: Rotation disagreement left (degrees first).
        changes: Each changed parameter: as it is, as it would match, the difference.
        details: More evidence or caveats, one line each.
        fix_toml: Model-file text that applies it, or empty.
        edits: Edits of the ``[[joint]]`` tables that apply it, one line each
            (``[[joint]] J3: flip = true``).
    """

    rank: int
    kind: str
    title: str
    explains: bool
    verdict: str
    position_after: Measure
    rotation_after: Measure
    changes: tuple[str, ...]
    details: tuple[str, ...]
    fix_toml: str
    edits: tuple[str, ...] = ()


@dataclass(frozen=True)
class AxisView:
    """One joint's axis from the table against the URDF's, as lines.

    Attributes:
        joint: ``"2 · shoulder_lift"``.
        urdf_joint: The URDF joint mapped to it.
        angle: Largest angle between the two directions (degrees first).
        distance: Largest distance between the two lines (none for a prismatic joint).
        status: ``agrees``, ``differs`` or ``reversed`` (anti-parallel: turns the other way).
        first: The first joint whose axis differs.
    """

    joint: str
    urdf_joint: str
    angle: Measure
    distance: Measure
    status: str
    first: bool


@dataclass(frozen=True)
class DiagnosisView:
    """What ``fkcheck diagnose`` finds for one disagreeing backend.

    Attributes:
        backend: The backend diagnosed.
        also: Other disagreeing backends with the same errors at every configuration
            of the check (within tolerance), which this diagnosis stands for.
        error: The diagnosis failed: the exception, in full (then nothing else is set).
        explained: Some explanation makes the disagreement vanish.
        verdict: One sentence: the most likely explanation, or that none was found.
        short: A few words for the page's first screen.
        configurations: How many configurations the diagnosis compared.
        position_before: The position disagreement as given, on those configurations.
        rotation_before: The rotation disagreement as given (degrees first).
        explanations: Most likely first.
        axes: Joint axes against the URDF (empty when the backend does not read it).
        axes_note: What the axes point at, in one line.
        tried: The hypotheses tried, one line each.
        command: The ``fkcheck diagnose`` command line that reproduces it.
        duration: How long it took, formatted.
    """

    backend: str
    also: tuple[str, ...]
    error: str
    explained: bool
    verdict: str
    short: str
    configurations: int
    position_before: Measure
    rotation_before: Measure
    explanations: tuple[ExplanationView, ...]
    axes: tuple[AxisView, ...]
    axes_note: str
    tried: tuple[str, ...]
    command: str
    duration: str


@dataclass(frozen=True)
class DhRow:
    """One row of the DH table as shown (lengths m, angles degrees).

    Attributes:
        index: Row number, 1-based.
        joint: Joint name.
        type: ``revolute`` or ``prismatic``.
        a: Link length.
        alpha: Link twist.
        d: Link offset.
        theta: Joint angle offset.
        flip: ``yes`` when the joint turns the other way.
        limits: Joint limits.
        urdf_joint: The URDF joint mapped to it, if any.
        variable: Which of θ or d the joint value drives.
    """

    index: int
    joint: str
    type: str
    a: str
    alpha: str
    d: str
    theta: str
    flip: str
    limits: str
    urdf_joint: str
    variable: str


@dataclass(frozen=True)
class TransformView:
    """A fixed transform (the base or tool).

    Attributes:
        label: ``"base (world → DH frame 0)"`` or similar.
        summary: xyz (m) and rpy (degrees), or ``"identity"``.
        matrix: The 4×4 matrix.
    """

    label: str
    summary: str
    matrix: MatrixView


@dataclass(frozen=True)
class FrameRow:
    """One named frame of the model's mapping.

    Attributes:
        name: Frame name.
        placement: DH frame it is attached to.
        offset: Fixed offset from there.
        urdf: URDF twin, if any.
        compared: ``from`` / ``to`` when this check compares it.
    """

    name: str
    placement: str
    offset: str
    urdf: str
    compared: str


@dataclass(frozen=True)
class ModelView:
    """The model as the report shows it.

    Attributes:
        name: Model name.
        description: Free text from the model file.
        source: Where its numbers come from.
        path: The model file.
        convention: ``standard`` or ``modified``.
        convention_formula: ``A_i`` as a product of elementary motions.
        a_matrix: ``A_i`` written out, 4 rows of 4 symbolic entries.
        variable_note: How θ and d depend on the joint value.
        rows: The DH table.
        base: Base transform.
        tool: Tool transform.
        frames: Named frames.
        urdf: The reference URDF as written in the model file, or empty.
    """

    name: str
    description: str
    source: str
    path: str
    convention: str
    convention_formula: str
    a_matrix: tuple[tuple[str, ...], ...]
    variable_note: str
    rows: tuple[DhRow, ...]
    base: TransformView
    tool: TransformView
    frames: tuple[FrameRow, ...]
    urdf: str


@dataclass(frozen=True)
class EvidenceLine:
    """What the check proved of one kind of evidence.

    Attributes:
        kind: ``implementation`` or ``table``.
        status: ``verified``, ``failed``, ``expected-failure`` or ``not-checked``.
        text: The sentence (see :func:`fkcheck.engine.verdict.evidence_sentences`).
    """

    kind: str
    status: str
    text: str


@dataclass(frozen=True)
class NumberRow:
    """One number of the model in the report's table of numbers.

    Attributes:
        name: ``d1``, ``[base] z``, ``[frames.base_link] rz``.
        group: ``joint 1 (shoulder_pan)``, ``[base]``, ``[frames.NAME]``.
        value: Its value in the model, formatted (mm or degrees).
        status: After the check: ``verified``, ``failed``, ``not-checked``,
            ``not-identifiable``, ``not-covered`` or ``vouched``.
        note: Its resolution, what could absorb it, what it trades with, its source.
    """

    name: str
    group: str
    value: str
    status: str
    note: str


@dataclass(frozen=True)
class NumbersView:
    """What the compared frame pair verified of the model, number by number.

    Attributes:
        line: The one-line summary every output shows.
        rows: One row per number.
    """

    line: str
    rows: tuple[NumberRow, ...]


@dataclass(frozen=True)
class ReportPage:
    """One model's report page.

    Attributes:
        title: Page title.
        model: Model name.
        verdict: ``pass``, ``fail``, ``error`` or ``unverified``.
        verdict_line: The verdict as a sentence, e.g. "3 of 5 backends disagree".
        verdict_headline: The verdict with what it proved, e.g. "pass — implementation
            only; table not checked against anything independent".
        evidence: One line per kind of evidence (implementation, table).
        badge_note: Under the verdict badge: ``"implementation only"`` for a pass
            whose table nothing independent checked (the badge is then not green).
        disagreeing: Names of the backends that fail.
        headline: The largest errors among the disagreeing backends.
        facts: What was checked and how (key/value list), library versions and
            the command line that reproduces the check.
        sides: The two compared frames and what they mean.
        backends: One row per backend.
        plots: Error distribution and error against each joint.
        partings: Where the chains part: DH frames of backends built from the
            table, and the table's joint axes against the URDF's.
        details: One section per disagreeing backend.
        model_view: The model.
        generator: ``fkcheck <version>``.
        diagnoses: What ``fkcheck diagnose`` finds, per distinct disagreement
            (empty when the check passed or the diagnosis was not asked for).
        jacobian: The Jacobian section (``check --jacobian``), or ``None``.
        numbers: The model's numbers and what the check verified of each, or ``None``.
        calibration: What a calibrated model's calibration changes, one line
            (``""`` for other models).
    """

    title: str
    model: str
    verdict: str
    verdict_line: str
    verdict_headline: str
    evidence: tuple[EvidenceLine, ...]
    badge_note: str
    disagreeing: tuple[str, ...]
    headline: tuple[str, ...]
    facts: tuple[Fact, ...]
    sides: tuple[FrameSide, ...]
    backends: tuple[BackendRow, ...]
    plots: tuple[Image, ...]
    partings: tuple[PartingView, ...]
    details: tuple[BackendDetail, ...]
    model_view: ModelView
    generator: str
    diagnoses: tuple[DiagnosisView, ...] = ()
    jacobian: JacobianSection | None = None
    numbers: NumbersView | None = None
    calibration: str = ""


@dataclass(frozen=True)
class IndexRow:
    """One model × backend line of the index.

    Attributes:
        backend: Backend name.
        status: Its status.
        pos_max: Largest position error.
        rot_max: Largest rotation error.
        message: Skip/error reason or failure summary.
    """

    backend: str
    status: str
    pos_max: Measure
    rot_max: Measure
    message: str


@dataclass(frozen=True)
class IndexModel:
    """One model on the index page.

    Attributes:
        name: Model name.
        verdict: Its verdict.
        report: Relative link to its HTML report.
        json: Relative link to its JSON result.
        junit: Relative link to its JUnit XML.
        pair: The compared frame pair, e.g. ``"base → tool0"``.
        configurations: Number of configurations checked.
        rows: One row per backend.
        table_evidence: ``verified``, ``partly-verified``, ``failed``,
            ``expected-failure`` or ``not-checked``.
        evidence_text: What verified the table, or why nothing did.
        numbers_text: How many table numbers the check verified, left not
            identifiable and did not cover.
    """

    name: str
    verdict: str
    report: str
    json: str
    junit: str
    pair: str
    configurations: int
    rows: tuple[IndexRow, ...]
    table_evidence: str = "not-checked"
    evidence_text: str = ""
    numbers_text: str = ""


@dataclass(frozen=True)
class IndexPage:
    """The dashboard: every model × backend.

    Attributes:
        title: Page title.
        verdict: ``pass`` when every model passes, else ``fail``, ``error`` or ``unverified``.
        verdict_line: The verdict as a sentence.
        facts: Run facts (date, versions, command).
        models: One entry per model.
        generator: ``fkcheck <version>``.
        badge_note: Under a pass badge when some models' tables were checked for
            implementation only (the badge is then not green).
    """

    title: str
    verdict: str
    verdict_line: str
    facts: tuple[Fact, ...]
    models: tuple[IndexModel, ...]
    generator: str
    badge_note: str = ""
