"""navkf.diagnose: the command line's diagnosis on a dataset in memory."""

import json
import subprocess

import numpy as np

import pytest

import navkf
from conftest import SHORT, interrupted_at_start


def test_diagnose_equals_the_command_line(cli, pair, tmp_path):
    pair.write(tmp_path / "pair")
    subprocess.run([str(cli), "diagnose", str(tmp_path / "pair"), "--out", str(tmp_path / "cli")], check=True, capture_output=True)
    expected = json.loads((tmp_path / "cli" / "diagnosis.json").read_text())
    seen = []
    got = navkf.diagnose(pair, out=tmp_path / "py", progress=lambda d, t: seen.append(d))
    series = got.pop("series")
    # The dataset's name is its folder's: the same data under two names.
    expected["dataset"] = got["dataset"]
    assert got == expected
    assert (tmp_path / "py" / "report.md").exists()
    assert "odometer-scale" in got["effects"]
    # The series: the base model's misfit falls once the named effects are in.
    model, before = series["model"], series["before"]
    assert set(model["innovation"]) == {"v_x", "v_y", "L", "lambda"}
    assert model["t"].shape == model["nis"].shape == model["innovation"]["v_x"].shape
    assert np.nanmean(before["nis"]) > np.nanmean(model["nis"])
    assert model["effects"] == got["effects"]


def test_with_adds_an_effect_and_the_verdict_is_a_word(pair):
    d = navkf.diagnose(pair, with_=["odometer-scale", "gps-latency"], max_rounds=1)
    assert isinstance(d["verdict"], str)
    assert d["rounds"][0]["kind"] == "manual"


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"with_": ["drag"]}, "with: unknown platform effect `drag`"),
        ({"with_": ["gps-latency", "gps-latency"]}, "given twice"),
        ({"window": 0.0}, "window 0"),
        ({"max_rounds": 0}, "max_rounds 0"),
        ({"priors": {"Kg0x": -1.0}}, "prior Kg0x"),
        ({"priors": {"nope": 1.0}}, "prior nope"),
        ({"azimuth_sigma": 3.0}, "azimuth_sigma"),
        ({"noise": "guess"}, "noise 'guess'"),
        ({"filter": "kalman"}, "filter: unknown filter"),
    ],
)
def test_bad_settings_are_named_as_python_spells_them(pair, kwargs, message):
    with pytest.raises(navkf.NavkfError, match=message):
        navkf.diagnose(pair, **kwargs)


def test_ctrl_c_stops_a_diagnosis_and_writes_nothing(tmp_path):
    out = tmp_path / "out"
    code, rest = interrupted_at_start(
        'ds = navkf.simulate(seed=3, effects="odometer-scale=0.005,gps-latency=0.2")\n',
        f"navkf.diagnose(ds, out={str(out)!r}, progress=progress)",
    )
    assert code == 130, rest
    assert "interrupted" in rest
    assert not out.exists()


def test_a_unit_mistake_is_warned_before_the_verdict(pair):
    inputs = {k: (v if k == "t" else v / 9.80665) for k, v in pair.inputs.items()}  # in g
    ds = navkf.Dataset.from_arrays(inputs, pair.measurements)
    assert ds.warnings()
    with pytest.warns(UserWarning, match="in g"):
        navkf.diagnose(ds, noise="stated", max_rounds=1)


def test_effects_declared_in_a_file_reach_simulate_and_diagnose(cli, root, tmp_path):
    """An effects file (docs/declared-effects.md) is taken as the command line takes it:
    `simulate` may hide its effects, `diagnose` tries them, and the answer is the command
    line's, bit for bit."""
    effects = root / "studies" / "effects" / "examples.toml"
    ds = navkf.simulate(
        seed=5,
        trajectory=SHORT,
        effects="drag,kd=-2e-4",
        effects_file=effects,
        out=tmp_path / "drag",
    )
    assert 'name = "drag"' in (tmp_path / "drag" / "dataset.toml").read_text()
    subprocess.run(
        [str(cli), "diagnose", str(tmp_path / "drag"), "--effects-file", str(effects),
         "--out", str(tmp_path / "cli")],
        check=True,
        capture_output=True,
    )
    expected = json.loads((tmp_path / "cli" / "diagnosis.json").read_text())
    got = navkf.diagnose(tmp_path / "drag", effects_file=effects)
    got.pop("series")
    assert got == expected
    assert "drag" in got["effects"]
    # The file's other effects are candidates too: `with_` may name them.
    d = navkf.diagnose(ds, effects_file=effects, with_="gps-offset", max_rounds=1)
    assert d["rounds"][0]["kind"] == "manual"
    with pytest.raises(navkf.NavkfError, match="unknown platform effect `gps-offset`"):
        navkf.diagnose(ds, with_="gps-offset")


def test_an_effects_file_of_the_other_family_is_refused_by_name(pair, root, tmp_path):
    strapdown = root / "studies" / "effects" / "strapdown-examples.toml"
    platform = root / "studies" / "effects" / "examples.toml"
    said = "strapdown-examples.toml: declares strapdown effects"
    with pytest.raises(navkf.NavkfError, match=said):
        navkf.diagnose(pair, effects_file=strapdown)
    with pytest.raises(navkf.NavkfError, match=said):
        navkf.simulate(effects_file=strapdown, out=tmp_path / "refused")
    with pytest.raises(navkf.NavkfError, match="examples.toml: declares platform effects"):
        navkf.simulate(model="strapdown", effects_file=platform, out=tmp_path / "refused")
    assert not (tmp_path / "refused").exists()
    bad = tmp_path / "bad.toml"
    bad.write_text('[[effect]]\nname = "x"\ncoefficients = []\nplaces = [{ coefficient = "c", place = "E_q" }]\n')
    with pytest.raises(navkf.NavkfError, match=r"bad.toml: effect\[0\]"):
        navkf.diagnose(pair, effects_file=bad)
