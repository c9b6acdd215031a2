"""navkf.study and navkf.plan: the command line's numbers, as Python data."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import navkf
from conftest import interrupted_at_start

# Timing and provenance differ between any two runs; everything else must match bit for bit.
VARYING = {"step_ns_median", "step_ns_p90", "command", "wall_s", "machine"}


def strip(value):
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items() if k not in VARYING}
    if isinstance(value, list):
        return [strip(v) for v in value]
    return value


def test_study_equals_the_command_line_for_the_same_seed(cli, root, tmp_path):
    subprocess.run(
        [str(cli), "study", str(root / "studies" / "ci.toml"), "--runs", "6", "--out", str(tmp_path / "cli"), "--quiet"],
        check=True,
        capture_output=True,
    )
    expected = json.loads((tmp_path / "cli" / "summary.json").read_text())
    seen = []
    result = navkf.study(root / "studies" / "ci.toml", runs=6, out=tmp_path / "py", progress=lambda d, t: seen.append((d, t)))
    assert strip(result.summary) == strip(expected)
    assert strip(json.loads((tmp_path / "py" / "summary.json").read_text())) == strip(expected)
    assert (tmp_path / "cli" / "rms_over_time.csv").read_text() == (tmp_path / "py" / "rms_over_time.csv").read_text()
    assert seen and seen[-1][1] == 6
    assert len(result.runs) == 6 and [r["run"] for r in result.runs] == list(range(6))
    assert {f["filter"] for f in result.runs[0]["filters"]} == {"ekf", "standard_ukf", "simplified_ukf"}
    series = result.series
    assert set(series["filter"]) == {"ekf", "standard_ukf", "simplified_ukf"}
    assert np.all(np.isfinite(series["t"]))


def test_the_baseline_copies_give_the_same_study_to_the_bit(cli, root, tmp_path):
    # The command line forced to its plain x86-64 kernels (NAVKF_SIMD=baseline) against this
    # process, which runs the AVX2 + FMA copies where the CPU has them (docs/speed.md).
    assert navkf.instruction_set() in {"avx2-fma", "baseline", "native"}
    env = dict(os.environ, NAVKF_SIMD="baseline")
    subprocess.run(
        [str(cli), "study", str(root / "studies" / "ci.toml"), "--runs", "4", "--out", str(tmp_path / "cli"), "--quiet"],
        check=True,
        capture_output=True,
        env=env,
    )
    report = (tmp_path / "cli" / "report.md").read_text()
    assert "the build's baseline target" in report or "compiled in" in report
    expected = json.loads((tmp_path / "cli" / "summary.json").read_text())
    result = navkf.study(root / "studies" / "ci.toml", runs=4)
    assert strip(result.summary) == strip(expected)


def test_a_study_from_a_dict(root):
    result = navkf.study({"study": {"name": "tiny", "runs": 2, "seed": 5, "filters": ["ekf"]}, "trajectory": {"duration_s": 1000.0, "leg_north_m": 3000.0, "leg_east_m": 2000.0}})
    assert result.summary["runs"] == 2
    assert list(result.summary["filters"]) == ["ekf"]


@pytest.mark.parametrize(
    "study, message",
    [
        ({"study": {"name": "x", "seed": 1, "runs": 2, "filters": ["kalman"]}}, "kalman"),
        ({"study": {"name": "x", "seed": 1, "runz": 2}}, "runz"),
        ("no/such/file.toml", "no/such/file.toml"),
    ],
)
def test_bad_study_files_are_named(study, message):
    with pytest.raises(navkf.NavkfError, match=message):
        navkf.study(study)


def test_the_diagnosis_study_and_sweeps_say_where_they_run(root):
    with pytest.raises(navkf.NavkfError, match="diagnosis study"):
        navkf.study(root / "studies" / "diagnosis.toml")
    with pytest.raises(navkf.NavkfError, match="sweeps"):
        navkf.study(root / "studies" / "misalignment.toml")


def test_plan_equals_the_command_line(cli, root, tmp_path):
    subprocess.run([str(cli), "plan", str(root / "studies" / "paper.toml"), "--out", str(tmp_path / "cli")], check=True, capture_output=True)
    expected = json.loads((tmp_path / "cli" / "plan.json").read_text())
    assert navkf.plan(root / "studies" / "paper.toml") == expected


def test_ctrl_c_stops_a_study_and_writes_nothing(root, tmp_path):
    out = tmp_path / "out"
    code, rest = interrupted_at_start(
        "",
        f"navkf.study({str(root / 'studies' / 'ci.toml')!r}, runs=400, out={str(out)!r}, progress=progress)",
    )
    assert code == 130, rest
    assert "interrupted" in rest
    assert not out.exists()
    assert not any(n.name.startswith(".out.navkf-partial") for n in tmp_path.iterdir())


def test_an_ignored_instruction_set_setting_is_warned_about_on_import():
    # NAVKF_SIMD=plain is no value the kernels know: importing says so, as the command line
    # does; baseline says nothing.
    def imported(value):
        env = dict(os.environ, NAVKF_SIMD=value)
        return subprocess.run(
            [sys.executable, "-W", "always", "-c", "import navkf"],
            capture_output=True,
            text=True,
            env=env,
        )

    plain = imported("plain")
    assert plain.returncode == 0, plain.stderr
    assert "RuntimeWarning" in plain.stderr and 'NAVKF_SIMD="plain" is ignored' in plain.stderr
    quiet = imported("baseline")
    assert quiet.returncode == 0 and "NAVKF_SIMD" not in quiet.stderr, quiet.stderr
