"""navkf.Filter stepped by hand: the same numbers as a run, and clear errors."""

import numpy as np
import pytest

import navkf


def run_by_hand(pair, kind):
    f = navkf.Filter(kind, pair, effects=["odometer-scale", "gps-latency"])
    t = pair.measurements["t"]
    nis, loglik = [], []
    for i in range(len(t)):
        if t[i] <= f.t + 1e-9:
            continue
        f.predict_to(t[i])
        z, sigma, available = f.observation(i)
        f.update(z, sigma, available)
        nis.append(f.nis)
        loglik.append(f.log_likelihood)
    return f, np.array(nis), np.array(loglik)


@pytest.mark.parametrize("kind", ["ekf", "simplified_ukf"])
def test_stepping_by_hand_equals_step(pair, kind):
    f, nis, loglik = run_by_hand(pair, kind)
    g = navkf.Filter(kind, pair, effects=["odometer-scale", "gps-latency"])
    nis2 = []
    while g.step() is not None:
        nis2.append(g.nis)
    np.testing.assert_array_equal(nis, np.array(nis2))
    np.testing.assert_array_equal(f.x, g.x)
    np.testing.assert_array_equal(f.P, g.P)


def test_the_filter_finds_the_hidden_effects_and_is_consistent(pair):
    f, nis, loglik = run_by_hand(pair, "ekf")
    names = f.state_names
    kod = f.x[names.index("kod")]
    sigma = np.sqrt(f.P[names.index("kod"), names.index("kod")])
    assert abs(kod - 0.005) < 4 * sigma
    # Four channels per update: the mean NIS is within its chi-square band over ~900 updates.
    assert 3.7 < nis.mean() < 4.3
    assert f.S.shape == (len(f.channels), len(f.channels))
    assert np.allclose(f.P, f.P.T)
    assert f.innovation.shape == (len(f.channels),)
    # The log-likelihood is the Gaussian density of the innovation under S.
    s, nu = f.S, f.innovation
    k = len(nu)
    expected = -0.5 * (nu @ np.linalg.solve(s, nu) + np.log(np.linalg.det(s)) + k * np.log(2 * np.pi))
    assert f.log_likelihood == pytest.approx(expected, rel=1e-9)


def test_predict_with_explicit_inputs_equals_predict_to(pair):
    a = navkf.Filter("ekf", pair)
    b = navkf.Filter("ekf", pair)
    ti = pair.inputs["t"]
    t0 = a.t
    t1 = pair.measurements["t"][pair.measurements["t"] > t0][0]
    knots = ti[(ti >= t0 - 1e-9) & (ti <= t1 + 1e-9)]
    u = np.column_stack([np.interp(knots, ti, pair.inputs[c]) for c in ("f_e", "f_n", "f_u")])
    a.predict(knots, u)
    b.predict_to(t1)
    np.testing.assert_allclose(a.x, b.x, rtol=0, atol=1e-12)
    assert a.t == pytest.approx(t1)


def test_reset_returns_to_the_start(pair):
    f = navkf.Filter("standard_ukf", pair)
    x0, p0 = f.x.copy(), f.P.copy()
    for _ in range(5):
        f.step()
    f.reset()
    np.testing.assert_array_equal(f.x, x0)
    f.reset(x0 + 1e-3 * (np.arange(len(x0)) == 0), p0)
    assert f.x[0] == x0[0] + 1e-3


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda f: f.update([1.0, 2.0], [1.0, 1.0]), "z: 2 values; expected 4"),
        (lambda f: f.update([np.nan, 0, 0, 0], [1, 1, 1, 1]), "expected a finite value"),
        (lambda f: f.update([0, 0, 0, 0], [0, 1, 1, 1]), "one-sigma > 0"),
        (lambda f: f.update("abc", [1, 1, 1, 1]), "not an array of numbers"),
        (lambda f: f.predict([0.0], [[0.0, 0.0, 0.0]]), "at least 2 knots"),
        (lambda f: f.predict([1.0, 2.0], [[0.0, 0.0]]), r"u: shape"),
        (lambda f: f.predict_to(float("nan")), "expected a time after"),
        (lambda f: f.reset(np.zeros(3)), "x0: 3 values"),
        (lambda f: f.reset(None, np.eye(2)), "P0: shape"),
        (lambda f: f.observation(10**9), "the dataset has"),
        (lambda f: f.nis, "no update since"),
    ],
)
def test_bad_input_raises_a_clear_error(pair, call, message):
    f = navkf.Filter("ekf", pair)
    with pytest.raises(navkf.NavkfError, match=message):
        call(f)


def test_unknown_kind_and_effect_are_named(pair):
    with pytest.raises(navkf.NavkfError, match="unknown filter `kalman`"):
        navkf.Filter("kalman", pair)
    with pytest.raises(navkf.NavkfError, match="unknown platform effect `drag`; known effects:"):
        navkf.Filter("ekf", pair, effects=["drag"])


def test_absurd_measurements_give_an_error_or_finite_numbers_never_nan(pair):
    f = navkf.Filter("ekf", pair)
    f.step()
    try:
        for _ in range(20):
            f.update([1e150, -1e150, 1e3, -1e3], [1e-150] * 4)
            f.predict_to(f.t + 1.0)
    except navkf.NavkfError as e:
        assert "step" in str(e) or "positive" in str(e), str(e)
    else:
        assert np.all(np.isfinite(f.x)) and np.all(np.isfinite(f.P))


def test_a_strapdown_filter_steps_through_a_mems_drive(tmp_path):
    from conftest import SHORT

    ds = navkf.simulate(model="strapdown", unit="mems", imu_rate=10, trajectory=SHORT, seed=9)
    f = navkf.Filter("simplified_ukf", ds)
    assert "speed" in f.channel_names
    nis, dims = [], []
    while f.step() is not None:
        nis.append(f.nis)
        dims.append(len(f.channels))
    assert len(nis) > 900
    assert np.all(np.isfinite(f.x)) and np.all(np.isfinite(nis))
    # A dataset in files holds the constraint's readings as exact zeros (docs/strapdown.md)
    # while the filter allows them the stated 0.1 m/s: those channels add almost nothing,
    # so the NIS per channel sits near one half (0.61 on this seed), not near 1.
    assert 0.4 < np.sum(nis) / np.sum(dims) < 1.0
    with pytest.raises(navkf.NavkfError, match=r"u: shape"):
        f.predict([f.t, f.t + 0.1], np.zeros((2, 3)))
