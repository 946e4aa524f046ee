"""Hostile and odd input to the readers of numbers and files (issue 15): model TOML and DH
CSV, `fk --q` and `--q-file`, measured poses `poses:FILE.csv`, and `check`'s numeric options.

Each case runs the command line and asserts exit 2, exactly one line on stderr naming the
file/field and the problem, no traceback, no file changed, and a time bound. Cases that
could hang if a reader opened what it was given (a FIFO, /dev/zero) run in a subprocess
with a timeout. Then the other side: what must keep working (a byte-order mark, identical
duplicate rows, 64- and 256-joint models, a 40 000-row poses file, chunked fk output).
"""

from __future__ import annotations

import errno
import io
import json
import os
import re
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.backends.measured import MeasuredPoses, read_poses_file
from fkcheck.cli.main import main
from fkcheck.core.pose_formats import pose_from_matrix
from fkcheck.engine.runner import run_check
from fkcheck.io.files import classify_path
from fkcheck.model.frames import reference_poses, relative_pose
from fkcheck.model.joint_input import read_q_file
from fkcheck.model.read import model_from_dict
from fkcheck.model.sampling import MAX_CORNERS, sample_configurations, sampling_box
from fkcheck.model.types import MAX_JOINT_RAD, MAX_LENGTH_M
from tests.paths import DATA_DIR
from tests.rtde_cases import RTDE_HEADER, rtde_rows
from tests.xacro_cases import TOP, write_description, write_model

#: Every case ends well within this (measured: under 0.5 s in-process, ~2 s in a subprocess).
TIME_BOUND_S = 20.0

HEAD = 'name = "m"\nconvention = "standard"\n'
JOINT = "[[joint]]\na = 0.1\nalpha = 0.0\nd = 0.2\n"
UR5_PENDANT = DATA_DIR / "ur5_pendant.csv"
PENDANT_HEAD = (
    "# fkcheck poses: from=base to=tool0\n"
    "q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,rx,ry,rz\n"
)
ZERO_ROW = "0,0,0,0,0,0,-817.250,-191.450,-5.491,1.570796,0.000000,0.000000\n"
SEED_ROW = "30,-60,90,-120,-90,45,-505.612,-417.951,178.795,2.492393,1.912480,0.000000\n"


def _joint(a: str = "0.1", extra: str = "") -> str:
    return f"[[joint]]\na = {a}\nalpha = 0.0\nd = 0.2\n{extra}"


def _deep_toml(depth: int) -> str:
    return HEAD + "x = " + "[" * depth + "]" * depth + "\n"


def _big_file(path: Path, size: int) -> None:
    with path.open("wb") as f:  # sparse: no disk space used
        f.truncate(size)


# --------------------------------------------------------------------------- the cases
# Each: id -> (files {name: text | bytes | "FIFO" | "DIR" | callable(path)}, argv, regex).
# "{tmp}" in argv is the case's directory; a regex names the file/field and the problem.

MODEL_TOML = {
    "toml_400_digit_integer": (
        {"m.toml": HEAD + _joint("9" * 400)},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: joint\[0\]\.a: number too large: an integer of about 40\d digits",
    ),
    "toml_5000_digit_integer": (
        {"m.toml": HEAD + JOINT + "[frames.f]\ndh = " + "9" * 5000 + "\n"},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: number too large: an integer of more than \d+ digits",
    ),
    "toml_length_overflows_fk": (
        {"m.toml": HEAD + _joint("1e308") + _joint("1e308")},
        ["fk", "m.toml", "--q", "0,0"],
        r"m\.toml: joint\[0\]\.a: 1e\+308 m is beyond ±1000 m",
    ),
    "toml_d_beyond_bound": (
        {"m.toml": HEAD + "[[joint]]\na = 0.1\nalpha = 0.0\nd = -1000.5\n"},
        ["fk", "m.toml", "--q", "0"],
        r"joint\[0\]\.d: -1000\.5 m is beyond ±1000 m",
    ),
    "toml_limits_overflow_sampling_box": (
        {"m.toml": HEAD + _joint(extra="limits = [-1.7e308, 1.7e308]\n")},
        ["check", "m.toml", "--against", "rtb-dh"],
        r"joint\[0\]\.limits\[0\]: -1\.7e\+308 rad is beyond ±1000 rad",
    ),
    "toml_prismatic_limit": (
        {"m.toml": HEAD + _joint(extra='type = "prismatic"\nlimits = [0.0, 5e3]\n')},
        ["fk", "m.toml", "--q", "0"],
        r"joint\[0\]\.limits\[1\]: 5000 m is beyond ±1000 m",
    ),
    "toml_degree_limit_beyond_bound": (
        {"m.toml": HEAD + 'angle_unit = "deg"\n' + _joint(extra="limits = [-1e5, 1e5]\n")},
        ["fk", "m.toml", "--q", "0"],
        r"joint\[0\]\.limits\[0\]: -1745\.33 rad is beyond ±1000 rad",
    ),
    "toml_base_xyz": (
        {"m.toml": HEAD + JOINT + "[base]\nxyz = [0.0, 1e300, 0.0]\n"},
        ["fk", "m.toml", "--q", "0"],
        r"base\.xyz\[1\]: 1e\+300 m is beyond ±1000 m",
    ),
    "toml_frame_xyz": (
        {"m.toml": HEAD + JOINT + "[frames.f]\ndh = 1\nxyz = [0.0, 0.0, 2e3]\n"},
        ["fk", "m.toml", "--q", "0"],
        r"frames\.f\.xyz\[2\]: 2000 m is beyond ±1000 m",
    ),
    "toml_pose_value": (
        {"m.toml": HEAD + JOINT + "[poses]\nfar = [1e6]\n"},
        ["fk", "m.toml", "--q", "0"],
        r"poses\.far\[0\]: 1e\+06 rad is beyond ±1000 rad",
    ),
    "toml_nested_3000_deep": (
        {"m.toml": _deep_toml(3000)},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: not valid TOML: arrays or tables nested too deeply",
    ),
    "toml_inline_tables_nested_deep": (
        {"m.toml": HEAD + "x = " + "{a = " * 3000 + "1" + "}" * 3000 + "\n"},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: not valid TOML: arrays or tables nested too deeply",
    ),
    "toml_key_with_newline": (
        {"m.toml": HEAD + '"x\\nverdict: pass" = 1\n' + JOINT},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: 'x\\nverdict: pass': unknown key",
    ),
    "toml_long_choice_value": (
        {"m.toml": 'name = "m"\nconvention = "' + "x" * 100_000 + '"\n' + JOINT},
        ["fk", "m.toml", "--q", "0"],
        r"convention: 'x{40}'… \(100000 characters\) is not one of: standard, modified",
    ),
    "toml_not_utf8_line_3": (
        {"m.toml": HEAD.encode() + b"description = '\xff'\n" + JOINT.encode()},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: line 3: not UTF-8 text",
    ),
    "toml_larger_than_1_mib": (
        {"m.toml": lambda p: _big_file(p, (1 << 20) + 1)},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: file too large: 1048577 bytes \(at most 1 MiB\)",
    ),
    "model_is_a_directory": (
        {"m.toml": "DIR"},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: is a directory, not a regular file",
    ),
    "model_is_dev_zero": (
        {},
        ["fk", "/dev/zero", "--q", "0"],
        r"/dev/zero: is a character device, not a regular file",
    ),
    "model_is_a_dangling_symlink": (
        {"m.toml": lambda p: p.symlink_to("gone.toml")},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: is a symlink to gone\.toml, which does not exist$",
    ),
    "model_path_goes_through_a_file": (
        {"m.toml": HEAD + JOINT},
        ["fk", "m.toml/x.toml", "--q", "0"],
        r"m\.toml/x\.toml: no such file$",
    ),
}

DH_CSV = {
    "csv_empty_field": (
        {"t.csv": "j1,0.1,,0.2,0\n"},
        ["fk", "t.csv", "--q", "0"],
        r"t\.csv: line 1\.alpha \(column 8\): empty field",
    ),
    "csv_missing_field_shifts_columns": (
        {"t.csv": "j1,0.1,,0.2\n"},
        ["fk", "t.csv", "--q", "0"],
        r"t\.csv: line 1: expected 5 comma-separated fields .* got 4",
    ),
    "csv_underscore": (
        {"t.csv": "j1,1_0,0,0.2,0\n"},
        ["fk", "t.csv", "--q", "0"],
        r"line 1\.a \(column 4\): not a number: '1_0' \(no '_' in numbers\)",
    ),
    "csv_arabic_indic_digits": (
        {"t.csv": "j1,٠٫١,0,0.2,0\n"},
        ["fk", "t.csv", "--q", "0"],
        r"line 1\.a \(column 4\): not a number: '٠٫١' \(non-ASCII characters",
    ),
    "csv_fullwidth_digits": (
        {"t.csv": "j1,0.1,0,０.２,0\n"},
        ["fk", "t.csv", "--q", "0"],
        r"line 1\.d \(column 10\): not a number: '０\.２' \(non-ASCII",
    ),
    "csv_nan": (
        {"t.csv": "j1,0.1,NaN,0.2,0\n"},
        ["fk", "t.csv", "--q", "0"],
        r"line 1\.alpha \(column 8\): must be finite, got 'NaN'",
    ),
    "csv_hex_float": (
        {"t.csv": "j1,0x1p-3,0,0.2,0\n"},
        ["fk", "t.csv", "--q", "0"],
        r"line 1\.a \(column 4\): not a number: '0x1p-3' \(no hex numbers\)",
    ),
    "csv_400_digit_integer": (
        {"t.csv": "j1," + "9" * 400 + ",0,0.2,0\n"},
        ["fk", "t.csv", "--q", "0"],
        r"line 1\.a \(column 4\): number too long: 400 characters \(at most 100\)",
    ),
    "csv_beyond_float": (
        {"t.csv": "j1,0.1,0,1e999,0\n"},
        ["fk", "t.csv", "--q", "0"],
        r"line 1\.d \(column 10\): number too large: '1e999'",
    ),
    "csv_length_beyond_bound": (
        {"t.csv": "j1,1e308,0,0.2,0\n"},
        ["fk", "t.csv", "--q", "0"],
        r"t\.csv: joint\[0\]\.a \(j1\): 1e\+308 m is beyond ±1000 m",
    ),
}

Q_ARG = {
    "q_empty_field": (
        {},
        ["fk", "ur5", "--q", "0.1,,0.2,0,0,0"],
        r"--q: value 2: empty field",
    ),
    "q_trailing_separator": (
        {},
        ["fk", "ur5", "--q", "0,0,0,0,0,0,"],
        r"--q: value 7: empty field",
    ),
    "q_underscore": (
        {},
        ["fk", "ur5", "--q", "1_0,0,0,0,0,0", "--ignore-limits"],
        r"--q: value 1: not a number: '1_0' \(no '_' in numbers\)",
    ),
    "q_arabic_indic_digit": (
        {},
        ["fk", "ur5", "--q", "0,١,0,0,0,0"],
        r"--q: value 2: not a number: '١' \(non-ASCII characters",
    ),
    "q_fullwidth_digit": (
        {},
        ["fk", "ur5", "--q", "0,0,１,0,0,0"],
        r"--q: value 3: not a number: '１' \(non-ASCII",
    ),
    "q_infinity": (
        {},
        ["fk", "ur5", "--q", "0,0,0,-Infinity,0,0", "--ignore-limits"],
        r"--q: value 4: must be finite, got '-Infinity'",
    ),
    "q_hex": (
        {},
        ["fk", "ur5", "--q", "0x10,0,0,0,0,0"],
        r"--q: value 1: not a number: '0x10' \(no hex numbers\)",
    ),
    "q_400_digits": (
        {},
        ["fk", "ur5", "--q", "9" * 400 + ",0,0,0,0,0", "--ignore-limits"],
        r"--q: value 1: number too long: 400 characters",
    ),
    "q_beyond_float": (
        {},
        ["fk", "ur5", "--q", "1e400,0,0,0,0,0", "--ignore-limits"],
        r"--q: value 1: number too large: '1e400'",
    ),
    "q_beyond_bound_with_ignore_limits": (
        {},
        ["fk", "ur5", "--q", "1e300,0,0,0,0,0", "--ignore-limits"],
        r"joint shoulder_pan = 1e\+300 rad is beyond ±1000 rad",
    ),
    "q_space_inside_number": (
        {},
        ["fk", "ur5", "--q", "0,0 0,0,0,0,0"],
        r"--q: value 2: not a number: '0 0' \(a space inside a number, or a missing separator\)",
    ),
}

Q_FILE = {
    "qfile_is_a_directory": (
        {"q": "DIR"},
        ["fk", "ur5", "--q-file", "q"],
        r"q: is a directory, not a regular file",
    ),
    "qfile_empty_field": (
        {"q.csv": "0,0,0,0,0,0\n0,0,,0,0,0\n"},
        ["fk", "ur5", "--q-file", "q.csv"],
        r"q\.csv: line 2: column 5 \(value 3\): empty field",
    ),
    "qfile_underscore": (
        {"q.csv": "# radians\n0,0,0,0,0,1_0\n"},
        ["fk", "ur5", "--q-file", "q.csv", "--ignore-limits"],
        r"q\.csv: line 2: column 11 \(value 6\): not a number: '1_0'",
    ),
    "qfile_arabic_indic": (
        {"q.csv": "0,0,0,0,٣,0\n"},
        ["fk", "ur5", "--q-file", "q.csv"],
        r"q\.csv: line 1: column 9 \(value 5\): not a number: '٣'",
    ),
    "qfile_nan": (
        {"q.csv": "0,0,0,0,0,nan\n"},
        ["fk", "ur5", "--q-file", "q.csv"],
        r"q\.csv: line 1: column 11 \(value 6\): must be finite, got 'nan'",
    ),
    "qfile_line_longer_than_64_kib": (
        {"q.csv": "0," * 40_000 + "0\n"},
        ["fk", "ur5", "--q-file", "q.csv"],
        r"q\.csv: line 1: longer than 64 KiB \(the limit per line\)",
    ),
    "qfile_larger_than_256_mib": (
        {"q.csv": lambda p: _big_file(p, (256 << 20) + 1)},
        ["fk", "ur5", "--q-file", "q.csv"],
        r"q\.csv: file too large: 268435457 bytes \(at most 256 MiB\)",
    ),
    "qfile_not_utf8": (
        {"q.csv": b"0,0,0,0,0,0\n0,0,\xe9,0,0,0\n"},
        ["fk", "ur5", "--q-file", "q.csv"],
        r"q\.csv: line 2: not UTF-8 text",
    ),
    "qfile_missing": (
        {},
        ["fk", "ur5", "--q-file", "nope.csv"],
        r"nope\.csv: no such file",
    ),
    "qfile_beyond_bound": (
        {"q.csv": "0,0,0,0,0,0\n0,0,0,0,0,5e3\n"},
        ["fk", "ur5", "--q-file", "q.csv", "--ignore-limits"],
        r"configuration 2: joint wrist_3 = 5000 rad is beyond ±1000 rad",
    ),
}

POSES = {
    "poses_is_a_directory": (
        {"p.csv": "DIR"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: is a directory, not a regular file",
    ),
    "diagnose_poses_is_a_directory": (
        {"p.csv": "DIR"},
        ["diagnose", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: is a directory, not a regular file",
    ),
    "poses_is_dev_zero": (
        {},
        ["check", "ur5", "--against", "poses:/dev/zero"],
        r"/dev/zero: is a character device, not a regular file",
    ),
    "poses_duplicate_column": (
        {"p.csv": "q1,q2,q3,q4,q5,q6,x,y,z,x,rx,ry,rz\n" + "0," * 12 + "0\n"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 1, column 25: column 'x' is named twice \(also field 7\)",
    ),
    "poses_unnamed_column": (
        {"p.csv": "q1,q2,q3,q4,q5,q6,x,y,z,rx,,ry,rz\n"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 1, column 28: a header field without a name",
    ),
    "poses_same_q_two_poses": (
        {"p.csv": PENDANT_HEAD + ZERO_ROW + SEED_ROW + SEED_ROW.replace("-505.612", "494.388")},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: lines 4 and 5 have the same configuration but poses differing by 1 m "
        r"and 0 rad",
    ),
    "poses_same_q_within_tolerance_two_poses": (
        {
            "p.csv": PENDANT_HEAD
            + SEED_ROW
            + SEED_ROW.replace("30,", "30.00000000001,", 1).replace("2.492393", "2.5")
        },
        ["check", "ur5", "--against", "poses:p.csv"],
        r"lines 3 and 4 have the same configuration \(within 1e-09\) but poses differing by "
        r"0 m and 0\.0\d+ rad",
    ),
    "poses_empty_field": (
        {"p.csv": PENDANT_HEAD + "30,-60,90,-120,-90,45,,-417.951,178.795,2.49,1.91,0\n"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 3, column 23 \(x_mm\): empty field",
    ),
    "poses_underscore": (
        {"p.csv": PENDANT_HEAD + "3_0,-60,90,-120,-90,45,1,2,3,0,0,0\n"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 3, column 1 \(q1_deg\): not a number: '3_0'",
    ),
    "poses_arabic_indic": (
        {"p.csv": PENDANT_HEAD + "30,-60,90,-120,-90,45,1,2,3,0,0,٠\n"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 3, column 33 \(rz\): not a number: '٠'",
    ),
    "poses_missing_field": (
        {"p.csv": PENDANT_HEAD + "30,-60,90,-120,-90,45,1,2,3,0,0\n"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 3: 11 fields, but the header names 12",
    ),
    "poses_position_beyond_bound": (
        {"p.csv": PENDANT_HEAD + "30,-60,90,-120,-90,45,1e300,2,3,0,0,0\n"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 3 \(x_mm\): 1e\+297 m is beyond ±1000 m",
    ),
    "poses_quaternion_beyond_bound": (
        {"p.csv": "q1,q2,q3,q4,q5,q6,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,0,0,1e308,1e308,0,0\n"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 2 \(qx\): 1e\+308 is beyond ±1000$",
    ),
    "poses_not_utf8": (
        {"p.csv": PENDANT_HEAD.encode() + b"\x80\n"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 3: not UTF-8 text",
    ),
}

#: A UR RTDE recording (space-separated, as UR's recorder writes it) and its fields.
RTDE_HEAD = " ".join(RTDE_HEADER) + "\n"
RTDE_FIELDS = [repr(v) for v in rtde_rows(load_model("ur5"), np.zeros((1, 6)))[0]]
RTDE_ARGV = ["check", "ur5", "--against", "poses:r.csv"]


def _rtde_row(**fields: str) -> str:
    """The zero configuration's row with some fields (by header name) replaced."""
    row = list(RTDE_FIELDS)
    for name, text in fields.items():
        row[RTDE_HEADER.index(name)] = text
    return " ".join(row) + "\n"


def _rtde_too_large(path: Path) -> None:
    with path.open("w", encoding="utf-8") as f:
        f.write(RTDE_HEAD + _rtde_row())
        f.truncate((4 << 30) + 1)  # 4 GiB and a byte (sparse): beyond a recording's limit


def _rtde_binary(path: Path) -> None:
    """What ``record.py --binary`` writes: names, a line of types, then packed numbers."""
    import struct

    types = ["INT32" if n == "robot_mode" else "DOUBLE" for n in RTDE_HEADER]
    packed = struct.pack(">" + "d" * len(RTDE_HEADER), *np.linspace(0.1, 2.7, len(RTDE_HEADER)))
    path.write_bytes((RTDE_HEAD + " ".join(types) + "\n").encode() + packed * 3)


RTDE = {
    "rtde_actual_q_0_twice": (
        {"r.csv": RTDE_HEAD.replace("target_q_0", "actual_q_0") + _rtde_row()},
        RTDE_ARGV,
        r"r\.csv: line 1: column actual_q_0 is named twice \(fields 2 and 20\)",
    ),
    "rtde_missing_pose_columns": (
        {"r.csv": RTDE_HEAD.replace("actual_TCP_pose", "target_TCP_pose") + _rtde_row()},
        RTDE_ARGV,
        r"r\.csv: line 1: an RTDE recording \(its header names actual_q_0\) needs columns "
        r"actual_TCP_pose_0, actual_TCP_pose_1, .*, actual_TCP_pose_5; record the outputs",
    ),
    "rtde_nan": (
        {"r.csv": RTDE_HEAD + _rtde_row() + _rtde_row(actual_q_2="nan")},
        RTDE_ARGV,
        r"r\.csv: line 3, field 22 \(actual_q_2\): must be finite, got 'nan'$",
    ),
    "rtde_inf": (
        {"r.csv": RTDE_HEAD + _rtde_row(actual_TCP_pose_4="-inf")},
        RTDE_ARGV,
        r"r\.csv: line 2, field 12 \(actual_TCP_pose_4\): must be finite, got '-inf'$",
    ),
    "rtde_too_few_fields": (
        {"r.csv": RTDE_HEAD + _rtde_row() + _rtde_row().rsplit(" ", 1)[0] + "\n"},
        RTDE_ARGV,
        rf"r\.csv: line 3: {len(RTDE_HEADER) - 1} fields, but the header names "
        rf"{len(RTDE_HEADER)}$",
    ),
    "rtde_beyond_4_gib": (
        {"r.csv": _rtde_too_large},
        RTDE_ARGV,
        r"r\.csv: file too large: 4294967297 bytes \(at most 4096 MiB\)",
    ),
    "rtde_binary_recording": (
        {"r.csv": _rtde_binary},
        RTDE_ARGV,
        r"r\.csv: line 2: a binary RTDE recording \(record\.py --binary: .*\); record it "
        r"without --binary$",
    ),
    "rtde_binary_junk": (
        {"r.csv": RTDE_HEAD.encode() + bytes(range(255, -1, -1)) * 8},
        RTDE_ARGV,
        r"r\.csv: line 2: not UTF-8 text$",
    ),
    "rtde_comma_in_a_space_separated_field": (
        {"r.csv": RTDE_HEAD + _rtde_row(actual_q_0="0,5")},
        RTDE_ARGV,
        r"r\.csv: line 2, field 20 \(actual_q_0\): not a number: '0,5'",
    ),
}

CHECK_OPTIONS = {
    "seed_negative": (
        {},
        ["check", "ur5", "--seed", "-1"],
        r"--seed: must be an integer from 0 to 2\*\*64",
    ),
    "seed_beyond_64_bits": (
        {},
        ["check", "ur5", "--seed", str(2**64)],
        r"--seed: must be an integer from 0 to 2\*\*64 - 1 \(.*\), got 18446744073709551616",
    ),
    "samples_huge": (
        {},
        ["check", "ur5", "--samples", "10000000000000"],
        r"--samples: must be an integer from 0 to 10_000_000 \(.*\), got 10000000000000",
    ),
    "samples_scientific": (
        {},
        ["check", "ur5", "--samples", "1e13"],
        r"argument --samples: invalid int value: '1e13'",
    ),
    "samples_negative": (
        {},
        ["check", "ur5", "--samples", "-1"],
        r"--samples: must be an integer from 0",
    ),
    "timeout_beyond_a_day": (
        {},
        ["check", "ur5", "--timeout", "1e10"],
        r"--timeout: must be > 0 and at most 86400 s \(.*\), got 1e\+10",
    ),
    "timeout_nan": ({}, ["check", "ur5", "--timeout", "nan"], r"--timeout: must be > 0"),
    "diagnose_seed_negative": (
        {},
        ["diagnose", "ur5", "--against", "rtb-dh", "--seed", "-1"],
        r"--seed: must be an integer from 0 to 2\*\*64 - 1 \(.*\), got -1",
    ),
}

XACRO = "d/robot/arm.urdf.xacro"
PACKAGE = "arm_description=d/arm_description"
#: The xacro description, with a mesh whose file name $(find …) writes into the URDF.
MESH_TOP = TOP.replace(
    '<link name="base"/>',
    '<link name="base"><visual><geometry><mesh filename="file://$(find arm_description)/m.stl"/>'
    "</geometry></visual></link>",
)


def _xacro_model(directory: Path) -> None:
    """The description and its model (xacro = true) in ``directory``."""
    write_description(directory, MESH_TOP)
    packages = 'packages = { arm_description = "../arm_description" }'
    write_model(directory, "0.3", f"xacro = true\n{packages}")


#: Round three (issue 21): text arguments that are not UTF-8, unbounded time limits,
#: empty paths, poses of frames the model lacks.
ROUND_THREE = {
    "expand_arg_not_utf8": (
        {"d": write_description},
        ["expand", XACRO, "--package", PACKAGE, "--arg", "reach=1.0\udcff", "-o", "o.urdf"],
        r"^fkcheck expand: error: argument --arg: 'reach=1\.0\\udcff' is not UTF-8 text "
        r"\(byte 0xff\)",
    ),
    "expand_package_not_utf8": (
        {"d": write_description},
        ["expand", XACRO, "--package", "arm_description=d/\udcff", "-o", "o.urdf"],
        r"argument --package: 'arm_description=d/\\udcff' is not UTF-8 text",
    ),
    "map_arg_not_utf8": (
        {"d": write_description},
        ["map", "planar2", XACRO, "--allow-xacro", "--package", PACKAGE, "--arg", "reach=\udcff"],
        r"^fkcheck map: error: argument --arg: 'reach=\\udcff' is not UTF-8 text",
    ),
    "urdf_name_not_utf8": (
        {},
        ["urdf", "planar2", "-o", "o.urdf", "--name", "r\udcff"],
        r"argument --name: 'r\\udcff' is not UTF-8 text",
    ),
    "dh_from_urdf_name_not_utf8": (
        {"d": write_description},
        [
            "table-from",
            XACRO,
            "--allow-xacro",
            "--package",
            PACKAGE,
            "--base",
            "base",
            "--tip",
            "tip",
            "--name",
            "n\udcff",
            "-o",
            "o.toml",
        ],
        r"argument --name: 'n\\udcff' is not UTF-8 text",
    ),
    "expansion_from_a_directory_not_utf8": (
        {"\udcff": _xacro_model},
        ["check", "\udcff/robot/xarm.toml", "--against", "pinocchio-urdf", "--samples", "2"],
        r"arm\.urdf\.xacro: its expansion holds a byte that is not UTF-8 \(0xff, from a "
        r"directory or argument name\): a URDF cannot; rename it$",
    ),
    "expand_timeout_beyond_a_day": (
        {"d": write_description},
        ["expand", XACRO, "--package", PACKAGE, "--timeout", "1e300", "-o", "o.urdf"],
        r"^fkcheck: error: --timeout: must be > 0 and at most 86400 s \(.*\), got 1e\+300$",
    ),
    "expand_timeout_nan": (
        {"d": write_description},
        ["expand", XACRO, "--package", PACKAGE, "--timeout", "nan", "-o", "o.urdf"],
        r"--timeout: must be > 0 and at most 86400 s \(.*\), got nan$",
    ),
    "project_timeout_beyond_a_day": (
        {"pyproject.toml": "[tool.fkcheck]\ntimeout = 1e300\n"},
        ["check", "planar2"],
        r"pyproject\.toml: tool\.fkcheck\.timeout: must be > 0 and at most 86400 s \(.*\), "
        r"got 1e\+300$",
    ),
    "urdf_path_empty": (
        {"m.toml": HEAD + JOINT + '[urdf]\npath = ""\njoints = ["j"]\n'},
        ["check", "m.toml"],
        r"m\.toml: urdf\.path: '' names no file: give the URDF's path",
    ),
    "map_urdf_empty": (
        {},
        ["map", "planar2", ""],
        r"^fkcheck: error: '': names no file: give a URDF file's path, example-robot-data:",
    ),
    "poses_frame_the_model_lacks": (
        {"p.csv": PENDANT_HEAD.replace("to=tool0", "to=nosuch") + ZERO_ROW},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 1: '# fkcheck poses: from=… to=…': frame 'nosuch' not in model ur5; "
        r"frames are: ",
    ),
    "diagnose_poses_frame_the_model_lacks": (
        {"p.csv": PENDANT_HEAD.replace("from=base", "from=nobase") + ZERO_ROW},
        ["diagnose", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: line 1: .*frame 'nobase' not in model ur5",
    ),
}

#: Cases that would hang if a reader opened the file: run in a subprocess with a timeout.
HANGING = {
    "model_is_a_fifo": ({"m.toml": "FIFO"}, ["fk", "m.toml", "--q", "0"], r"m\.toml: is a FIFO"),
    "model_is_a_symlink_to_a_fifo": (
        {"pipe": "FIFO", "m.toml": lambda p: p.symlink_to("pipe")},
        ["fk", "m.toml", "--q", "0"],
        r"m\.toml: is a symlink to pipe, which is a FIFO \(named pipe\), not a regular file$",
    ),
    "qfile_is_a_fifo": (
        {"q.csv": "FIFO"},
        ["fk", "ur5", "--q-file", "q.csv"],
        r"q\.csv: is a FIFO \(named pipe\), not a regular file",
    ),
    "qfile_is_dev_zero": (
        {},
        ["fk", "ur5", "--q-file", "/dev/zero"],
        r"/dev/zero: is a character device, not a regular file",
    ),
    "poses_is_a_fifo": (
        {"p.csv": "FIFO"},
        ["check", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: is a FIFO \(named pipe\), not a regular file",
    ),
    "diagnose_poses_is_a_fifo": (
        {"p.csv": "FIFO"},
        ["diagnose", "ur5", "--against", "poses:p.csv"],
        r"p\.csv: is a FIFO \(named pipe\), not a regular file",
    ),
    "poses_bag_is_a_fifo": (
        {"rec.mcap": "FIFO"},
        ["check", "ur5", "--against", "poses:rec.mcap"],
        r"rec\.mcap: the bag is not a regular file$",
    ),
    "poses_bags_file_is_a_fifo": (
        {
            "bag": "DIR",
            "bag/metadata.yaml": "rosbag2_bagfile_information:\n  storage_identifier: mcap\n"
            "  relative_file_paths: [bag_0.mcap]\n",
            "bag/bag_0.mcap": "FIFO",
        },
        ["check", "ur5", "--against", "poses:bag"],
        r"bag: its file bag_0\.mcap is not a regular file$",
    ),
}

FAMILIES = {
    "model_toml": MODEL_TOML,
    "dh_csv": DH_CSV,
    "q_arg": Q_ARG,
    "q_file": Q_FILE,
    "poses_csv": POSES,
    "rtde_csv": RTDE,
    "check_options": CHECK_OPTIONS,
    "round_three": ROUND_THREE,
}
IN_PROCESS = [
    pytest.param(*case, id=f"{family}-{name}")
    for family, cases in FAMILIES.items()
    for name, case in cases.items()
]


def _make_files(root: Path, files: dict) -> None:
    for name, content in files.items():
        path = root / name
        if content == "FIFO":
            os.mkfifo(path)
        elif content == "DIR":
            path.mkdir()
        elif callable(content):
            content(path)
        elif isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8")


def _snapshot(root: Path) -> dict[str, tuple[int, int]]:
    return {
        str(p.relative_to(root)): (p.lstat().st_size, p.lstat().st_mtime_ns)
        for p in sorted(root.rglob("*"))
    }


def _assert_one_clear_line(code: int, err: str, match: str) -> None:
    assert code == 2, err
    assert "Traceback" not in err, err
    lines = err.strip("\n").split("\n")
    assert len(lines) == 1, err
    assert re.match(r"fkcheck( [\w-]+)?: error: ", lines[0]), err
    assert re.search(match, lines[0]), lines[0]


@pytest.mark.parametrize(("files", "argv", "match"), IN_PROCESS)
def test_hostile_input_is_one_line_and_exit_2(tmp_path, monkeypatch, capsys, files, argv, match):
    _make_files(tmp_path, files)
    monkeypatch.chdir(tmp_path)
    before = _snapshot(tmp_path)
    start = time.monotonic()
    code = main(argv)
    elapsed = time.monotonic() - start
    out, err = capsys.readouterr()
    _assert_one_clear_line(code, err, match)
    assert out == ""
    assert _snapshot(tmp_path) == before  # nothing written, nothing replaced
    assert elapsed < TIME_BOUND_S


@pytest.mark.parametrize(
    ("files", "argv", "match"),
    [pytest.param(*case, id=name) for name, case in HANGING.items()],
)
def test_hostile_file_kind_is_refused_unopened_in_a_subprocess(tmp_path, files, argv, match):
    _make_files(tmp_path, files)
    before = _snapshot(tmp_path)
    start = time.monotonic()
    proc = subprocess.run(
        [sys.executable, "-m", "fkcheck", *argv],
        cwd=tmp_path, capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    elapsed = time.monotonic() - start
    _assert_one_clear_line(proc.returncode, proc.stderr, match)
    assert proc.stdout == ""
    assert _snapshot(tmp_path) == before
    assert elapsed < TIME_BOUND_S


def test_classify_path_names_every_kind_in_one_wording_without_opening(tmp_path):
    import socket

    (tmp_path / "file").write_text("x", encoding="utf-8")
    (tmp_path / "dir").mkdir()
    os.mkfifo(tmp_path / "fifo")
    sock = socket.socket(socket.AF_UNIX)
    try:
        sock.bind(str(tmp_path / "sock"))
        (tmp_path / "to-fifo").symlink_to("fifo")
        (tmp_path / "to-nothing").symlink_to("gone")
        (tmp_path / "loop").symlink_to("loop")
        kinds = {  # opening "fifo" or "to-fifo" would block here: they are only looked at
            name: classify_path(tmp_path / name).describe()
            for name in ("file", "dir", "fifo", "sock", "to-fifo", "to-nothing", "loop", "none")
        }
    finally:
        sock.close()
    assert kinds == {
        "file": "a regular file",
        "dir": "a directory",
        "fifo": "a FIFO (named pipe)",
        "sock": "a socket",
        "to-fifo": "a symlink to fifo, which is a FIFO (named pipe)",
        "to-nothing": "a symlink to gone, which does not exist",
        "loop": f"a symlink to loop, which is a path that cannot be looked at "
        f"({os.strerror(errno.ELOOP)})",
        "none": "nothing (no such file)",
    }
    assert classify_path("/dev/null").describe() == "a character device"
    assert classify_path(tmp_path / "file" / "x").missing  # a file on the way: nothing there
    nul = classify_path("a\0b")
    assert (nul.stat, nul.errno, nul.reason) == (None, None, "the path holds a NUL character")


# --------------------------------------------------------------------------- what still works

BOM = "\ufeff"


def test_byte_order_mark_is_accepted_by_every_text_reader(tmp_path, capsys):
    model_text = HEAD + JOINT + JOINT.replace("0.1", "0.3")
    (tmp_path / "plain.toml").write_text(model_text, encoding="utf-8")
    (tmp_path / "bom.toml").write_text(BOM + model_text, encoding="utf-8")
    assert load_model(tmp_path / "bom.toml").joints == load_model(tmp_path / "plain.toml").joints
    csv_text = "# name,a,alpha,d,theta_offset\nj1,0.1,0.5,0.2,0\n"
    (tmp_path / "bom.csv").write_text(BOM + csv_text, encoding="utf-8")
    assert load_model(tmp_path / "bom.csv").joints[0].a == 0.1
    (tmp_path / "bom_first_row.csv").write_text(BOM + "j1,0.1,0.5,0.2,0\n", encoding="utf-8")
    assert load_model(tmp_path / "bom_first_row.csv").joints[0].name == "j1"
    ur5 = load_model("ur5")
    q_file = tmp_path / "q.csv"
    q_file.write_text(BOM + "0.1,0.2,0.3,0.4,0.5,0.6\n", encoding="utf-8")
    np.testing.assert_array_equal(read_q_file(q_file, ur5), [[0.1, 0.2, 0.3, 0.4, 0.5, 0.6]])
    poses = tmp_path / "poses.csv"
    poses.write_text(BOM + PENDANT_HEAD + ZERO_ROW, encoding="utf-8")
    q, _, pair = read_poses_file(poses, ur5)
    assert pair == ("base", "tool0")
    np.testing.assert_array_equal(q, np.zeros((1, 6)))
    poses.write_text(BOM + PENDANT_HEAD.split("\n", 1)[1] + ZERO_ROW, encoding="utf-8")
    assert read_poses_file(poses, ur5)[0].shape == (1, 6)  # the BOM before the header


def test_plain_numbers_in_every_spelling_are_read(capsys):
    code = main(["fk", "ur5", "--q", " +0.5 ;-.5, 3.e-1,1E-1 ,\t0 , 2.5e+0", "--json"])
    assert code == 0, capsys.readouterr().err
    assert json.loads(capsys.readouterr().out)["q_rad"] == [0.5, -0.5, 0.3, 0.1, 0.0, 2.5]


def _check_poses(model, path: Path, tol: float):
    backend = MeasuredPoses(str(path))
    return run_check(model, [backend], samples=0, tol_pos_m=tol, tol_rot_rad=tol)


def test_identical_duplicate_rows_are_fine(tmp_path):
    poses = tmp_path / "p.csv"
    # The same row twice, once with other spellings of the same numbers.
    same = SEED_ROW.replace("30,", "30.0,", 1).replace("0.000000\n", "-0\n")
    poses.write_text(PENDANT_HEAD + SEED_ROW + ZERO_ROW + same, encoding="utf-8")
    ur5 = load_model("ur5")
    result = _check_poses(ur5, poses, tol=1e-3)
    assert result.q.shape == (3, 6)
    assert result.backends[0].status == "pass", result.backends[0].message


def _pendant_rows(model, q_deg: np.ndarray) -> list[str]:
    q = np.radians(q_deg)
    T = relative_pose(*reference_poses(model, q, ("base", "tool0")))
    rows = np.hstack([q_deg, pose_from_matrix(T, "rotvec") * [1e3, 1e3, 1e3, 1, 1, 1]])
    return [",".join(repr(float(v)) for v in row) for row in rows]


def _keep_every_row(monkeypatch) -> None:
    """Keep 100,000 rows of a recording, not 20,000: every row is then matched, as it was."""
    from fkcheck.backends import recording

    monkeypatch.setattr(recording, "KEEP_ROWS", 100_000)


def test_40k_row_poses_file_is_matched_in_near_linear_time(tmp_path, rng, monkeypatch):
    _keep_every_row(monkeypatch)
    ur5 = load_model("ur5")
    q_deg = np.round(rng.uniform(-170, 170, size=(40_000, 6)), 3)
    poses = tmp_path / "p.csv"
    poses.write_text(PENDANT_HEAD + "\n".join(_pendant_rows(ur5, q_deg)) + "\n", encoding="utf-8")
    start = time.monotonic()
    result = _check_poses(ur5, poses, tol=1e-6)
    elapsed = time.monotonic() - start
    assert result.q.shape == (40_000, 6)
    assert result.backends[0].status == "pass", result.backends[0].message
    assert elapsed < 15.0  # measured ~1.5 s on 2 busy cores; quadratic matching took 56 s


def test_100k_row_rtde_recording_of_a_robot_often_standing_still_is_read_quickly(
    tmp_path, rng, monkeypatch
):
    from tests.rtde_cases import write_rtde_csv

    _keep_every_row(monkeypatch)
    ur5 = load_model("ur5")
    q = rng.uniform(-3.0, 3.0, size=(100_000, 6))
    q[1::3] = q[::3][: q[1::3].shape[0]]  # a third of the samples repeat the one before
    path = write_rtde_csv(tmp_path / "r.csv", ur5, q)
    start = time.monotonic()
    result = _check_poses(ur5, path, tol=1e-6)
    elapsed = time.monotonic() - start
    assert result.q.shape == (100_000, 6)
    assert result.backends[0].status == "pass", result.backends[0].message
    assert elapsed < 30.0  # measured 3–4 s on 2 shared cores (reading the file: ~1.5 s)


def test_poses_matched_within_tolerance_and_missing_ones_named(tmp_path):
    ur5 = load_model("ur5")
    poses = tmp_path / "p.csv"
    poses.write_text(PENDANT_HEAD + SEED_ROW + ZERO_ROW, encoding="utf-8")
    backend = MeasuredPoses(str(poses))
    q = backend.configurations(ur5)
    nudged = q + np.array([[5e-10], [-5e-10]])  # not bit for bit a row, within MATCH_TOL
    np.testing.assert_array_equal(
        backend.frame_poses(ur5, nudged, ("base", "tool0")),
        backend.frame_poses(ur5, q, ("base", "tool0")),
    )
    from fkcheck.backends.base import BackendUnavailable

    with pytest.raises(BackendUnavailable, match="no pose for configuration 1"):
        backend.frame_poses(ur5, q + np.array([[0.0], [2e-9]]), ("base", "tool0"))


def _chain_model(n: int):
    joints = [
        {"name": f"j{i}", "a": 0.01, "alpha": 0.3, "d": 0.02, "limits": [-1.0, 2.0]}
        for i in range(n)
    ]
    return model_from_dict({"name": f"arm{n}", "convention": "standard", "joint": joints})


@pytest.mark.parametrize("n", [8, 9, 62, 63, 64, 256])
def test_corner_sampling_works_up_to_256_joints(n):
    model = _chain_model(n)
    samples = sample_configurations(model, 5, seed=11)
    corners = samples.q[np.array(samples.origin) == "corner"]
    assert corners.shape == (min(2**n, MAX_CORNERS), n)
    assert len(np.unique(corners, axis=0)) == corners.shape[0]  # distinct corners
    lo, hi = sampling_box(model)
    assert ((corners == lo) | (corners == hi)).all()
    assert np.isfinite(samples.q).all()
    again = sample_configurations(model, 5, seed=11)
    np.testing.assert_array_equal(again.q, samples.q)  # seeded
    other = sample_configurations(model, 5, seed=12)
    if 2**n > MAX_CORNERS:
        assert not np.array_equal(other.q, samples.q)


def test_a_64_joint_model_is_checked(capsys):
    model = _chain_model(64)
    result = run_check(model, _dh_backends(), samples=20)
    assert result.verdict == "pass", [b.message for b in result.backends]


def _dh_backends():
    from fkcheck.backends.registry import parse_against

    return parse_against(["pinocchio-dh"])


def test_model_bounds_are_the_documented_ones():
    assert (MAX_LENGTH_M, MAX_JOINT_RAD) == (1e3, 1e3)
    at_bound = HEAD + "[[joint]]\na = 1000.0\nalpha = 0.0\nd = -1000.0\nlimits = [-1000, 1000]\n"
    import tomllib

    model = model_from_dict(tomllib.loads(at_bound))
    assert model.joints[0].a == 1000.0
    assert np.isfinite(model.fk(np.array([1000.0]))).all()


def test_fk_output_in_chunks_is_the_one_call_output(monkeypatch, rng):
    import argparse

    import fkcheck.cli.fk as fk_command
    import fkcheck.core.dh

    def args(all_frames: bool) -> argparse.Namespace:
        return argparse.Namespace(all_frames=all_frames, frame_from=None, frame_to=None)

    model = load_model("ur5")
    q = rng.uniform(-3, 3, (37, 6))
    monkeypatch.setattr(fk_command, "_CHUNK", 16)
    monkeypatch.setattr(fkcheck.core.dh, "JIT_MIN_POSES", 10)  # the whole batch "takes the JIT"
    chunks = list(fk_command._fk_chunks(model, q, args(False)))
    # 16 + 16 + 5: the short last chunk joins the one before, so every chunk is a JIT batch.
    assert [len(c) for c, _ in chunks] == [16, 21]
    np.testing.assert_array_equal(np.concatenate([T for _, T in chunks]), model.fk(q))
    monkeypatch.setattr(fkcheck.core.dh, "JIT_MIN_POSES", 20)  # chunks never below the JIT's size
    assert [len(c) for c, _ in fk_command._fk_chunks(model, q, args(False))] == [37]
    monkeypatch.setattr(fkcheck.core.dh, "JIT_MIN_POSES", 40)  # the whole batch on the NumPy path
    assert [len(c) for c, _ in fk_command._fk_chunks(model, q, args(False))] == [16, 16, 5]
    frames = list(fk_command._fk_chunks(model, q, args(True)))
    assert [len(c) for c, _ in frames] == [2] * 18 + [1]  # 16 // 7 configurations a chunk
    np.testing.assert_array_equal(
        np.concatenate([T for _, T in frames]), model.fk(q, all_frames=True)
    )


@pytest.mark.parametrize("fmt", ["matrix", "quat"])
def test_fk_q_file_json_is_byte_for_byte_one_json_array(tmp_path, capsys, monkeypatch, rng, fmt):
    import fkcheck.cli.fk as fk_command

    monkeypatch.setattr(fk_command, "_CHUNK", 4)  # several chunks
    q = rng.uniform(-1, 1, (11, 6))
    path = tmp_path / "q.csv"
    path.write_text("\n".join(",".join(repr(float(v)) for v in row) for row in q) + "\n")
    assert main(["fk", "ur5", "--q-file", str(path), "--json", "--format", fmt]) == 0
    out = capsys.readouterr().out
    records = json.loads(out)
    assert out == json.dumps(records) + "\n"
    assert len(records) == 11
    np.testing.assert_array_equal([r["q_rad"] for r in records], q)


class _CountingSink(io.TextIOBase):
    """Stands in for stdout: counts what is written, keeps nothing."""

    def __init__(self) -> None:
        self.chars = 0
        self.tail = ""

    def writable(self) -> bool:
        return True

    def write(self, text: str) -> int:
        self.chars += len(text)
        self.tail = (self.tail + text)[-8:]
        return len(text)


def test_fk_q_file_json_memory_is_the_configurations_and_one_chunk(tmp_path, monkeypatch, rng):
    # A million lines peaked at 4.1 GB: every record and the whole JSON string at once.
    # Here 6 000 lines in chunks of 1 000: all at once held ~20 MB of Python objects;
    # streaming holds q (0.3 MB), one chunk of poses (0.1 MB) and one chunk's records.
    import fkcheck.cli.fk as fk_command

    monkeypatch.setattr(fk_command, "_CHUNK", 1000)
    path = tmp_path / "q.csv"
    q = rng.uniform(-1, 1, (6000, 6))
    path.write_text("\n".join(",".join(repr(float(v)) for v in row) for row in q) + "\n")
    warm = tmp_path / "warm.csv"
    warm.write_text("0,0,0,0,0,0\n0,0,0,0,0,0\n")
    sink = _CountingSink()
    monkeypatch.setattr(sys, "stdout", sink)
    assert main(["fk", "ur5", "--q-file", str(warm), "--json"]) == 0  # imports done
    tracemalloc.start()
    try:
        assert main(["fk", "ur5", "--q-file", str(path), "--json"]) == 0
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert sink.tail.endswith("]]}]\n")
    assert sink.chars > 6000 * 500  # every record was written
    assert peak < 5e6, f"peak {peak / 1e6:.1f} MB"
