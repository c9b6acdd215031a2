"""navkf.simulate and navkf.Dataset: the command line's datasets, bit for bit, as arrays."""

import filecmp
import subprocess

import numpy as np
import pytest

import navkf
from conftest import SHORT


def test_simulate_writes_what_the_command_line_writes(cli, short, tmp_path):
    args = ["--seed", "3", "--run", "2", "--trajectory", str(short), "--effects", "gyro-fz,odometer-scale=0.002"]
    subprocess.run([str(cli), "simulate", "--out", str(tmp_path / "cli"), *args], check=True, capture_output=True)
    ds = navkf.simulate(seed=3, run=2, trajectory=short.read_text(), effects="gyro-fz,odometer-scale=0.002", out=tmp_path / "py")
    for name in ["inputs.csv", "measurements.csv", "truth.csv", "dataset.toml"]:
        assert filecmp.cmp(tmp_path / "cli" / name, tmp_path / "py" / name, shallow=False), name
    back = navkf.Dataset.read(tmp_path / "cli")
    for k, v in ds.measurements.items():
        np.testing.assert_array_equal(v, back.measurements[k])


def test_columns_are_the_files_columns_with_nan_for_empty_cells(pair):
    assert pair.model == "platform"
    assert list(pair.inputs) == ["t", "f_e", "f_n", "f_u"]
    assert list(pair.measurements) == ["t", "v_e", "v_n", "lat_deg", "lon_deg"]
    m = pair.measurements
    assert all(v.dtype == np.float64 and v.shape == m["t"].shape for v in m.values())
    assert np.all(np.diff(m["t"]) > 0)
    assert pair.truth is not None and "kod" in pair.truth
    assert len(pair) == len(m["t"])
    assert pair.noise["gps_m"] > 0
    assert pair.summary()["inputs"]["count"] == len(pair.inputs["t"])


def test_strapdown_datasets_carry_the_imu_columns(tmp_path):
    ds = navkf.simulate(model="strapdown", unit="mems", imu_rate=10, trajectory=SHORT, seed=2)
    assert ds.model == "strapdown"
    assert list(ds.inputs) == ["t", "w_x", "w_y", "w_z", "f_x", "f_y", "f_z"]
    assert list(ds.measurements) == ["t", "speed", "lat_deg", "lon_deg"]
    # Gravity on the z axis of a level unit at rest.
    assert abs(np.median(ds.inputs["f_z"][:50]) - 9.8) < 0.1
    ds.write(tmp_path / "again")
    assert navkf.Dataset.read(tmp_path / "again").inputs["f_z"].tolist() == ds.inputs["f_z"].tolist()
    # The body's sideslip and bounce move its readings; body_motion=0 holds it rigid.
    rigid = navkf.simulate(
        model="strapdown", unit="mems", imu_rate=10, trajectory=SHORT, seed=2, body_motion=0
    )
    assert rigid.inputs["f_x"].tolist() != ds.inputs["f_x"].tolist()
    assert rigid.noise.get("zupt_m_s") != ds.noise.get("zupt_m_s")


def test_write_never_replaces_a_folder_that_is_not_a_dataset(pair, tmp_path):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep me")
    with pytest.raises(navkf.NavkfError):
        pair.write(mine)
    assert (mine / "notes.txt").read_text() == "keep me"


def test_a_bad_file_is_named_with_its_line_and_column(pair, tmp_path):
    pair.write(tmp_path / "bad")
    lines = (tmp_path / "bad" / "inputs.csv").read_text().splitlines()
    cells = lines[5].split(",")
    cells[2] = "abc"
    lines[5] = ",".join(cells)
    (tmp_path / "bad" / "inputs.csv").write_text("\n".join(lines) + "\n")
    with pytest.raises(navkf.NavkfError, match=r"inputs.csv:6: column `f_n`"):
        navkf.Dataset.read(tmp_path / "bad")


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"effects": "no-such-effect"}, "no-such-effect"),
        ({"effects": {"Ka0x": 1e300}}, "beyond"),
        ({"model": "gimbal"}, "expected \"platform\" or \"strapdown\""),
        ({"unit": "mems"}, "unit: a strapdown setting"),
        ({"model": "strapdown", "imu_rate": 10.5}, "imu_rate 10.5"),
        ({"model": "strapdown", "body_motion": -0.1}, "body_motion -0.1"),
        ({"body_motion": 0.1}, "body_motion: a strapdown setting"),
        ({"azimuth_sigma": -1.0}, "azimuth_sigma -1"),
        ({"seed": -1}, "seed -1"),
        ({"trajectory": "[trajectory]\nduration_s = -5.0\n"}, "trajectory"),
    ],
)
def test_bad_settings_raise_navkf_errors_naming_the_setting(kwargs, message):
    with pytest.raises(navkf.NavkfError, match=message):
        navkf.simulate(**{"trajectory": SHORT, **kwargs})


def test_a_dataset_from_arrays_equals_the_folder_it_came_from(pair):
    back = navkf.Dataset.from_arrays(pair.inputs, pair.measurements, truth=pair.truth, name="mine")
    assert back.name == "mine"
    for k, v in pair.measurements.items():
        np.testing.assert_array_equal(v, back.measurements[k])
    for k, v in pair.inputs.items():
        np.testing.assert_array_equal(v, back.inputs[k])
    # No dataset.toml: navkf's default noise, which is not called stated.
    assert not back.noise_stated


def test_bad_arrays_are_named_with_their_row(pair):
    m = {k: v.copy() for k, v in pair.measurements.items()}
    m["lat_deg"][4] = 123.0
    with pytest.raises(navkf.NavkfError, match=r"measurements row 4"):
        navkf.Dataset.from_arrays(pair.inputs, m)
    with pytest.raises(navkf.NavkfError, match=r"missing \['f_u'\]"):
        navkf.Dataset.from_arrays({k: v for k, v in pair.inputs.items() if k != "f_u"}, m)
    with pytest.raises(navkf.NavkfError, match="lengths"):
        navkf.Dataset.from_arrays({**pair.inputs, "f_u": pair.inputs["f_u"][:-1]}, pair.measurements)
    with pytest.raises(navkf.NavkfError, match="not an array of numbers"):
        navkf.Dataset.from_arrays({**pair.inputs, "f_u": ["a"] * len(pair.inputs["t"])}, pair.measurements)
    # The families and their columns come from the native module's registration.
    with pytest.raises(navkf.NavkfError, match=r"model 'gimbal': expected 'platform' or 'strapdown'"):
        navkf.Dataset.from_arrays(pair.inputs, pair.measurements, model="gimbal")
    with pytest.raises(navkf.NavkfError, match=r"imu: columns .*expected exactly \['t', 'w_x'"):
        navkf.Dataset.from_arrays(pair.inputs, pair.measurements, model="strapdown")


def test_a_strapdown_dataset_from_arrays_states_its_family(tmp_path):
    ds = navkf.simulate(model="strapdown", imu_rate=10, trajectory=SHORT, seed=4)
    back = navkf.Dataset.from_arrays(ds.inputs, ds.measurements, model="strapdown")
    assert back.model == "strapdown"
    np.testing.assert_array_equal(back.inputs["w_z"], ds.inputs["w_z"])


def test_a_config_naming_another_family_is_refused():
    ds = navkf.simulate(model="strapdown", imu_rate=10, trajectory=SHORT, seed=4)
    with pytest.raises(navkf.NavkfError):
        navkf.Dataset.from_arrays(ds.inputs, ds.measurements, model="strapdown", config='[model]\nkind = "platform"\n')
