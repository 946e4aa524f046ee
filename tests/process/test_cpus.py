"""How many CPUs fkcheck may use: its affinity, capped by its cgroup's CPU quota."""

from __future__ import annotations

import os

from fkcheck.process import cpus


def test_a_cgroup_cpu_quota_caps_the_usable_cores(monkeypatch, tmp_path):
    # A container given 1.5 CPUs of a 64-core host: two processes, not 64.
    own = tmp_path / "self-cgroup"
    own.write_text("0::/ci/job\n")
    (tmp_path / "ci" / "job").mkdir(parents=True)
    (tmp_path / "ci" / "cpu.max").write_text("150000 100000\n")
    (tmp_path / "ci" / "job" / "cpu.max").write_text("max 100000\n")
    assert cpus.cpu_quota(tmp_path, own) == 2
    v1 = tmp_path / "v1"
    (v1 / "cpu").mkdir(parents=True)
    (v1 / "cpu" / "cpu.cfs_quota_us").write_text("300000\n")
    (v1 / "cpu" / "cpu.cfs_period_us").write_text("100000\n")
    assert cpus.cpu_quota(v1, tmp_path / "none") == 3
    (v1 / "cpu" / "cpu.cfs_quota_us").write_text("-1\n")
    assert cpus.cpu_quota(v1, tmp_path / "none") is None
    # v1: only the cpu controller's cgroup counts, not another controller's path.
    (v1 / "cpu" / "cpu.cfs_quota_us").write_text("-1\n")
    (v1 / "cpu" / "job").mkdir()
    (v1 / "cpu" / "job" / "cpu.cfs_quota_us").write_text("100000\n")
    (v1 / "cpu" / "job" / "cpu.cfs_period_us").write_text("100000\n")
    own.write_text("4:memory:/job\n1:cpu:/\n0::/\n")
    assert cpus.cpu_quota(v1, own) is None
    own.write_text("4:memory:/\n1:cpu,cpuacct:/job\n0::/\n")
    assert cpus.cpu_quota(v1, own) == 1
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(64)))
    monkeypatch.setattr(cpus, "cpu_quota", lambda: 2)
    assert cpus.usable_cores() == 2
    monkeypatch.setattr(cpus, "cpu_quota", lambda: None)
    assert cpus.usable_cores() == 64


def test_a_cgroup_outside_the_namespace_is_not_followed_above_the_mount(tmp_path):
    mount = tmp_path / "sys" / "fs" / "cgroup"
    mount.mkdir(parents=True)
    (tmp_path / "sys" / "fs" / "cpu.max").write_text("100000 100000\n")  # above the mount
    own = tmp_path / "self-cgroup"
    own.write_text("0::/../..\n")
    assert cpus.cpu_quota(mount, own) is None
    (mount / "cpu.max").write_text("200000 100000\n")
    assert cpus.cpu_quota(mount, own) == 2
