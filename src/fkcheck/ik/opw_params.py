"""OPW parameters of a DH table, derived by geometry and checked against OPW's own FK.

An *OPW* arm (Brandstötter, Angerer, Hofbaur, "An analytical solution of the inverse
kinematics problem of industrial serial manipulators with an ortho-parallel basis
and a spherical wrist", Austrian Robotics Workshop 2014) has six revolute joints:
axis 1 perpendicular to axis 2, axes 2 and 3 parallel, axis 4 perpendicular to them,
and a spherical wrist (axes 4, 5, 6 meeting in one point, each perpendicular to the
next). Seven lengths describe it — ``a1, a2, b, c1, c2, c3, c4`` — in OPW's zero
pose, the arm standing up along the base's z: axis 2 at ``(a1, ·, c1)``, axis 3
``c2`` above it, the wrist centre ``c3`` further along axis 4, offset ``a2`` from
axis 3 and ``b`` sideways, the flange ``c4`` beyond the wrist centre along axis 6.

A joint's angle reaches OPW as ``sign_correction · q − offset`` (the convention of
opw_kinematics, MoveIt's ``opw_kinematics`` YAML and py-opw-kinematics), so the
model's own joint zero and directions are kept: ``q`` is the model's.

:func:`derive_opw` reads the table's joint axes at ``q = 0`` (the DH frames of the
in-house FK, standard or modified, ``flip`` included) and measures the seven lengths,
the offsets and the signs from them, or says which condition of an OPW arm fails
(:class:`NotOpwShaped`). OPW's base frame is the model's world when axis 1 is the
world's z axis (up or down) through its origin, and OPW's tool frame is the model's
TCP when the TCP sits on axis 6 with its z along it; otherwise
:attr:`OpwParameters.world_T_base` and :attr:`OpwParameters.flange_T_tcp` hold the
fixed transforms between them (a MoveIt ``opw_kinematics`` plugin needs links at
those frames). :func:`opw_fk_deviation` then compares py-opw-kinematics' forward
kinematics with the table's on sampled configurations: the derivation shares no
code with that FK, so an agreement checks both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from fkcheck.core.geometry import invert
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.errors import FkcheckError
from fkcheck.model.types import Model

__all__ = [
    "GEOMETRY_TOL",
    "OPW_DOF",
    "NotOpwShaped",
    "OpwDeviation",
    "OpwParameters",
    "derive_opw",
    "opw_fk",
    "opw_fk_deviation",
    "opw_robot",
]

#: How far from exact a condition of an OPW arm may be: a cosine between axes that
#: must be perpendicular or parallel, or a distance (m) between axes that must
#: meet. A table typed in degrees or millimetres is exact to round-off (1e-16); a
#: real arm that is not OPW-shaped misses by millimetres or degrees.
GEOMETRY_TOL = 1e-9

#: OPW arms have this many joints.
OPW_DOF = 6
#: Configurations compared at a time (their poses, twice, are 16 MB).
_CHUNK = 1 << 16


class NotOpwShaped(FkcheckError):
    """The model is not an OPW arm: the message names the condition that fails.

    Attributes:
        model: The model's name.
        reason: The failing condition, with the measured value.
    """

    def __init__(self, model: str, reason: str) -> None:
        self.model = model
        self.reason = reason
        super().__init__(f"model {model}: not OPW-shaped: {reason}")


@dataclass(frozen=True, eq=False)
class OpwParameters:
    """An OPW arm's parameters, in opw_kinematics' conventions (metres, radians).

    Attributes:
        a1: Offset of axis 2 from axis 1, along OPW's base x in its zero pose.
        a2: Offset of axis 4 from axis 3 (the forearm's elbow offset).
        b: Sideways offset of the arm's plane from axis 1 (along axis 2).
        c1: Height of axis 2 above OPW's base origin.
        c2: Distance from axis 2 to axis 3 (upper arm).
        c3: Distance along axis 4 from the elbow to the wrist centre (forearm).
        c4: Distance from the wrist centre to the flange along axis 6.
        offsets: Per joint; OPW's angle is ``sign_corrections[i] · q[i] − offsets[i]``.
        sign_corrections: Per joint, ``1`` or ``-1``.
        world_T_base: OPW's base frame in the model's world (identity when the
            parameters hold for the model's world).
        flange_T_tcp: The model's TCP in OPW's tool frame (identity when the
            parameters reach the model's TCP).
    """

    a1: float
    a2: float
    b: float
    c1: float
    c2: float
    c3: float
    c4: float
    offsets: tuple[float, ...]
    sign_corrections: tuple[int, ...]
    world_T_base: Float = field(default_factory=lambda: np.eye(4))
    flange_T_tcp: Float = field(default_factory=lambda: np.eye(4))

    @property
    def lengths(self) -> dict[str, float]:
        """The seven lengths by name, in YAML order: a1, a2, b, c1, c2, c3, c4."""
        names = ("a1", "a2", "b", "c1", "c2", "c3", "c4")
        return {name: float(getattr(self, name)) for name in names}

    @property
    def base_is_world(self) -> bool:
        """Whether OPW's base frame is the model's world (no adapter needed)."""
        return bool(np.allclose(self.world_T_base, np.eye(4), rtol=0.0, atol=GEOMETRY_TOL))

    @property
    def tool_is_tcp(self) -> bool:
        """Whether OPW's tool frame is the model's TCP (no adapter needed)."""
        return bool(np.allclose(self.flange_T_tcp, np.eye(4), rtol=0.0, atol=GEOMETRY_TOL))


@dataclass(frozen=True)
class OpwDeviation:
    """How far OPW's FK is from the table's over sampled configurations.

    Attributes:
        samples: Configurations compared.
        max_position_m: Largest distance between the two TCP origins, metres.
        max_angle_rad: Largest angle between the two TCP orientations, radians.
    """

    samples: int
    max_position_m: float
    max_angle_rad: float


def _unit(v: Float) -> Float:
    unit: Float = v / np.linalg.norm(v)
    return unit


def _angle_deg(u: Float, v: Float) -> float:
    """Angle between two unit directions as lines (0…90°), degrees."""
    return math.degrees(math.acos(min(1.0, abs(float(u @ v)))))


def _sign(x: float) -> int:
    return -1 if x < 0.0 else 1


def _wrap(angle: float) -> float:
    """``angle`` in ``(-π, π]``; round-off about zero becomes 0.0."""
    wrapped = math.remainder(angle, 2.0 * math.pi)
    if wrapped == -math.pi:
        wrapped = math.pi
    return 0.0 if abs(wrapped) < GEOMETRY_TOL * 1e-3 else wrapped + 0.0


def _axes(model: Model) -> tuple[Float, Float]:
    """Joint axes at ``q = 0`` in the world: ``(points, directions)``, each ``(n, 3)``.

    Joint ``i`` turns about z of DH frame ``i − 1`` (standard) or ``i`` (modified),
    in the direction of its ``flip``.
    """
    frames = model.fk(np.zeros(model.dof), all_frames=True)
    k0 = 0 if model.convention == "standard" else 1
    points = np.array([frames[i + k0][:3, 3] for i in range(model.dof)])
    signs = np.array([-1.0 if j.flip else 1.0 for j in model.joints])
    dirs = np.array([frames[i + k0][:3, 2] for i in range(model.dof)]) * signs[:, None]
    return points, dirs


def _closest_point(points: Float, dirs: Float) -> tuple[Float, float]:
    """The point nearest to the lines (least squares) and its largest distance to one."""
    A = np.zeros((3, 3))
    rhs = np.zeros(3)
    for p, u in zip(points, dirs, strict=True):
        P = np.eye(3) - np.outer(u, u)
        A += P
        rhs += P @ p
    x: Float = np.asarray(np.linalg.lstsq(A, rhs, rcond=None)[0], dtype=np.float64)
    worst = max(
        float(np.linalg.norm(np.cross(x - p, u))) for p, u in zip(points, dirs, strict=True)
    )
    return x, worst


def _line_distance(p1: Float, u1: Float, p2: Float, u2: Float) -> float:
    """Distance between two lines (unit directions), parallel ones included."""
    cross = np.cross(u1, u2)
    norm = float(np.linalg.norm(cross))
    if norm <= GEOMETRY_TOL:
        return float(np.linalg.norm(np.cross(p2 - p1, u1)))
    return abs(float((p2 - p1) @ cross)) / norm


def _wrist_offset_name(model: Model, gap: float) -> str:
    """The table entry that holds the wrist's offset ``gap``, as ``joint[4].d (wrist_2)``."""
    rows = (3, 4) if model.convention == "standard" else (4, 5)  # 0-based rows between axes 4…6
    for i in rows:
        joint = model.joints[i]
        for name in ("a", "d"):
            value = float(getattr(joint, name))
            if value != 0.0 and abs(abs(value) - gap) <= GEOMETRY_TOL:
                return f" (the table's joint[{i}].{name} ({joint.name}) = {value:.12g} m)"
    return ""


def _check_shape(model: Model, P: Float, U: Float) -> None:
    """Raise :class:`NotOpwShaped` naming the first condition of an OPW arm that fails."""
    say = model.name
    if model.dof != OPW_DOF:
        raise NotOpwShaped(say, f"OPW arms have {OPW_DOF} joints, this table has {model.dof}")
    for i, joint in enumerate(model.joints):
        if joint.type != "revolute":
            raise NotOpwShaped(
                say, f"joint[{i}] ({joint.name}) is {joint.type}; OPW arms are all revolute"
            )
    _, worst = _closest_point(P[3:], U[3:])
    if worst > GEOMETRY_TOL:
        d45 = _line_distance(P[3], U[3], P[4], U[4])
        d56 = _line_distance(P[4], U[4], P[5], U[5])
        if d45 > GEOMETRY_TOL:
            detail = f"axes 4 and 5 do not meet ({d45:.6g} m apart)"
        elif d56 > GEOMETRY_TOL:
            detail = f"axes 5 and 6 do not meet ({d56:.6g} m apart)"
        else:
            w45, w56 = _closest_point(P[3:5], U[3:5]), _closest_point(P[4:6], U[4:6])
            gap = float(np.linalg.norm(w45[0] - w56[0]))
            detail = f"axes 4, 5 meet {gap:.6g} m from where axes 5, 6 meet"
            detail += _wrist_offset_name(model, gap)
        raise NotOpwShaped(
            say, f"axes 4, 5, 6 do not meet in one point (no spherical wrist): {detail}"
        )
    for i, j in ((3, 4), (4, 5)):
        if abs(float(U[i] @ U[j])) > GEOMETRY_TOL:
            raise NotOpwShaped(
                say,
                f"axes {i + 1} and {j + 1} of the wrist are not perpendicular "
                f"(at {_angle_deg(U[i], U[j]):.6g}° to each other)",
            )
    if abs(float(U[0] @ U[1])) > GEOMETRY_TOL:
        raise NotOpwShaped(
            say,
            f"axes 1 and 2 are not perpendicular (at {_angle_deg(U[0], U[1]):.6g}° to each other)",
        )
    if float(np.linalg.norm(np.cross(U[1], U[2]))) > GEOMETRY_TOL:
        raise NotOpwShaped(
            say, f"axes 2 and 3 are not parallel (at {_angle_deg(U[1], U[2]):.6g}° to each other)"
        )
    if float(np.linalg.norm(np.cross(P[2] - P[1], U[1]))) <= GEOMETRY_TOL:
        raise NotOpwShaped(say, "axes 2 and 3 are the same line (no upper arm: c2 = 0)")
    if abs(float(U[2] @ U[3])) > GEOMETRY_TOL:
        raise NotOpwShaped(
            say,
            "axis 4 is not perpendicular to axes 2 and 3 "
            f"(at {_angle_deg(U[2], U[3]):.6g}° to them)",
        )


def _base_frame(p1: Float, u1: Float, p2: Float) -> Float:
    """OPW's base frame: z along axis 1, origin on it nearest the world's origin.

    It is the world itself when axis 1 is the world's z axis (pointing up or down: a
    hanging arm keeps the world's z, and its lengths take the signs that go with
    it); otherwise its z points from the origin towards axis 2 (``p2``: ``c1 ≥ 0``)
    and its x is the world's x (or y) made perpendicular to it.
    """
    ez = np.array([0.0, 0.0, 1.0])
    if float(np.linalg.norm(np.cross(u1, ez))) <= GEOMETRY_TOL:
        z = ez
    else:
        z = u1 if float((p2 - p1) @ u1) >= 0.0 else -u1
    origin = p1 - float(p1 @ z) * z
    x = np.array([1.0, 0.0, 0.0]) - z[0] * z
    if float(np.linalg.norm(x)) < 0.5:
        x = np.array([0.0, 1.0, 0.0]) - z[1] * z
    x = _unit(x)
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, np.cross(z, x), z, origin
    if float(np.linalg.norm(origin)) <= GEOMETRY_TOL and np.allclose(
        T[:3, :3], np.eye(3), rtol=0.0, atol=GEOMETRY_TOL
    ):
        return np.eye(4)
    return T


def _rot(axis: Float, angle: float) -> Float:
    """Rotation by ``angle`` about the unit ``axis`` (Rodrigues), 3×3."""
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    R: Float = np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)
    return R


def derive_opw(model: Model) -> OpwParameters:
    """The OPW parameters of the model's table, measured on its joint axes at ``q = 0``.

    Args:
        model: A model with six revolute joints.

    Returns:
        The parameters; OPW's FK with them is the table's FK (see
        :func:`opw_fk_deviation` for the check).

    Raises:
        NotOpwShaped: The table is not an OPW arm; the message names the condition
            that fails (e.g. a UR's wrist: axes 4, 5, 6 do not meet in one point).
    """
    P_world, U_world = _axes(model)
    _check_shape(model, P_world, U_world)
    world_T_base = _base_frame(P_world[0], U_world[0], P_world[1])
    R_b, o_b = world_T_base[:3, :3], world_T_base[:3, 3]
    P = (P_world - o_b) @ R_b  # each row Rᵀ (p − o): the axes in OPW's base frame
    U = U_world @ R_b
    base_T_tcp = invert(world_T_base) @ model.fk(np.zeros(model.dof))
    ex, ey, ez = np.eye(3)

    # Joint 1 turns about +z; joint 2's axis is the arm's y (sign correction +1).
    s1 = _sign(float(U[0] @ ez))
    y = _unit(U[1] - float(U[1] @ ez) * ez)
    phi1 = math.atan2(-float(y @ ex), float(y @ ey))
    x_arm = np.cross(y, ez)
    wrist, _ = _closest_point(P[3:], U[3:])
    b = float(wrist @ y)
    A2 = P[1] + (b - float(P[1] @ y)) * y
    A3 = P[2] + (b - float(P[2] @ y)) / float(U[2] @ y) * U[2]
    a1, c1 = float(A2 @ x_arm), float(A2 @ ez)
    upper = A3 - A2
    c2 = float(np.linalg.norm(upper))
    phi2 = math.atan2(float(upper @ x_arm), float(upper @ ez))
    s3 = _sign(float(U[2] @ y))
    # Axis 4 points from the elbow towards the wrist centre (c3 ≥ 0).
    forearm = wrist - A3
    s4 = _sign(float(forearm @ U[3])) if abs(float(forearm @ U[3])) > GEOMETRY_TOL else 1
    z4 = s4 * U[3]
    phi23 = math.atan2(float(z4 @ x_arm), float(z4 @ ez))
    x_fore = np.cross(y, z4)
    a2, c3 = float(forearm @ x_fore), float(forearm @ z4)
    # Wrist: axis 5 as it is (sign +1); axis 6 points from the wrist centre to the TCP.
    y5 = U[4]
    phi4 = math.atan2(-float(y5 @ x_fore), float(y5 @ y))
    tcp = base_T_tcp[:3, 3]
    along = float((tcp - wrist) @ U[5])
    s6 = _sign(along) if abs(along) > GEOMETRY_TOL else 1
    z6 = s6 * U[5]
    c4 = abs(along)
    R_fore = np.column_stack([x_fore, y, z4])
    R_4 = R_fore @ _rot(ez, phi4)
    phi5 = math.atan2(float(z6 @ R_4[:, 0]), float(z6 @ R_4[:, 2]))
    R_5 = R_4 @ _rot(ey, phi5)
    R_tcp = base_T_tcp[:3, :3]
    if float(np.linalg.norm(R_tcp[:, 2] - z6)) <= GEOMETRY_TOL:
        phi6 = math.atan2(float(R_tcp[:, 0] @ R_5[:, 1]), float(R_tcp[:, 0] @ R_5[:, 0]))
    else:  # the TCP's z is not along axis 6: a fixed rotation after OPW's tool frame
        phi6 = 0.0
    base_T_flange = np.eye(4)
    base_T_flange[:3, :3] = R_5 @ _rot(ez, phi6)
    base_T_flange[:3, 3] = wrist + c4 * z6
    flange_T_tcp = invert(base_T_flange) @ base_T_tcp
    if np.allclose(flange_T_tcp, np.eye(4), rtol=0.0, atol=GEOMETRY_TOL):
        flange_T_tcp = np.eye(4)
    phis = (phi1, phi2, phi23 - phi2, phi4, phi5, phi6)
    a1, a2, b, c1, c2, c3, c4 = (
        0.0 if abs(v) <= GEOMETRY_TOL else v for v in (a1, a2, b, c1, c2, c3, c4)
    )
    return OpwParameters(
        a1=a1,
        a2=a2,
        b=b,
        c1=c1,
        c2=c2,
        c3=c3,
        c4=c4,
        offsets=tuple(_wrap(-phi) for phi in phis),
        sign_corrections=(s1, 1, s3, s4, 1, s6),
        world_T_base=world_T_base,
        flange_T_tcp=flange_T_tcp,
    )


def opw_robot(params: OpwParameters) -> object:
    """A py-opw-kinematics ``Robot`` with these parameters, joint angles in radians.

    Raises:
        ModuleNotFoundError: py-opw-kinematics is not installed (the ``ik`` extra).
    """
    from py_opw_kinematics import KinematicModel, Robot

    o = params.offsets
    f = [s < 0 for s in params.sign_corrections]
    kinematic = KinematicModel(
        a1=params.a1,
        a2=params.a2,
        b=params.b,
        c1=params.c1,
        c2=params.c2,
        c3=params.c3,
        c4=params.c4,
        offsets=(o[0], o[1], o[2], o[3], o[4], o[5]),
        flip_axes=(f[0], f[1], f[2], f[3], f[4], f[5]),
    )
    return Robot(kinematic, degrees=False)


def opw_fk(params: OpwParameters, q: Float, robot: object | None = None) -> Float:
    """``world_T_tcp`` by py-opw-kinematics' FK for ``(N, 6)`` configurations (the model's q).

    Args:
        params: The parameters.
        q: Joint values, radians, the model's order and zero, shape ``(N, 6)``.
        robot: A robot from :func:`opw_robot` to reuse (default: a new one).

    Returns:
        ``(N, 4, 4)``: OPW's base placed in the world, its tool frame carried to the TCP.
    """
    from py_opw_kinematics import Robot

    opw = robot if robot is not None else opw_robot(params)
    assert isinstance(opw, Robot)
    qs = np.ascontiguousarray(np.asarray(q, dtype=np.float64).reshape(-1, OPW_DOF))
    base_T_flange = np.asarray(opw.batch_forward(qs).as_matrix(), dtype=np.float64)
    world_T_tcp: Float = params.world_T_base @ base_T_flange.reshape(-1, 4, 4) @ params.flange_T_tcp
    return world_T_tcp


def opw_fk_deviation(
    model: Model, params: OpwParameters, samples: int = 1000, seed: int = 0
) -> OpwDeviation:
    """Compare py-opw-kinematics' FK with the table's on the check's configurations.

    The configurations are those a check draws
    (:func:`~fkcheck.model.sampling.sample_configurations`: named poses, zero,
    mid-range, limit corners and edges, then ``samples`` seeded random ones within
    the limits).

    Args:
        model: The model the parameters were derived from.
        params: Its parameters.
        samples: Random configurations on top of the structured ones.
        seed: Their seed.

    Returns:
        The largest position and rotation differences.
    """
    from fkcheck.model.sampling import sample_configurations

    q = sample_configurations(model, samples, seed).q
    robot = opw_robot(params)
    worst_m = worst_rad = 0.0
    for start in range(0, q.shape[0], _CHUNK):  # memory: one chunk of poses, not all
        chunk = q[start : start + _CHUNK]
        table, opw = model.fk(chunk), opw_fk(params, chunk, robot)
        worst_m = max(worst_m, float(position_error_m(table, opw).max()))
        worst_rad = max(worst_rad, float(rotation_error_rad(table, opw).max()))
    return OpwDeviation(samples=int(q.shape[0]), max_position_m=worst_m, max_angle_rad=worst_rad)
